"""Synthesis mathematics of [bapat2015, chs. 3, 5 and 6]: dyads, spring constants, the two-position and framework equations, segment sizing.

Angles are in degrees here, as in the dissertation's synthesis tables (chapters 3, 5, 6); the PRBM library they feed works in radians.
"""
