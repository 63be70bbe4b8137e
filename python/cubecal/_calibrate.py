"""Calibrations from Python: in the next commit."""
__all__ = []
