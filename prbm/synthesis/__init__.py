"""Synthesis mathematics of seed 000 chapters 3, 5 and 6: dyads, spring constants, the two-position and framework equations, segment sizing.

Angles are in degrees here, as in the seed's synthesis tables (chapters 3, 5, 6); the PRBM library they feed works in radians.
"""
