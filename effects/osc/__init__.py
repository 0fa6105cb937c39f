"""The `osc` effect: hands and gestures as OSC for Max, Pure Data and other patches."""
from effects.osc.effect import OscEffect

__all__ = ["OscEffect"]
