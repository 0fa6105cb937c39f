"""DigiEVISS: grab evidence spheres with gestures, link them, generate Forensic Lucid (thesis ch. 4.3.2)."""
from effects.digieviss.effect import DigiEVISS

__all__ = ["DigiEVISS"]
