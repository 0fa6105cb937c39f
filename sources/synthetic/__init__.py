"""The synthetic performer: the embedded default source (see source.py)."""
from sources.synthetic.source import SyntheticOptions, SyntheticSource

__all__ = ["SyntheticOptions", "SyntheticSource"]
