"""animstudio — scripted locomotion from gait scripts to USD skeletal animation.

Data flows one way (see docs/architecture.md)::

    script text --parse--> Script --engine--> GaitChannels --rig--> Clip --> USD / BVH / CSV / preview
"""

__version__ = "0.1.0"
