"""``python -m animstudio`` is the ``animstudio`` command."""

from animstudio.cli import main

main()
