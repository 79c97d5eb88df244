"""sleighsim: computational companion to "Chaotic dynamics of the Chaplygin sleigh
with a passive internal rotor" (Fedonyuk and Tallapragada)."""

__version__ = "0.1.0"
