"""Exporters. Each format is a pure builder plus a thin file wrapper that writes atomically."""
