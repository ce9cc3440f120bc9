"""Body proportions of the shipped humanoid character (metres).

Engines read these to turn dimensionless or model-sized motion into the character's size:
the Kohonen engine multiplies the thesis's hip deltas (in thigh lengths) by ``THIGH_M``; the
cpg engine scales its seed-sized body (0.4 m thigh, 0.5 m shank) to this leg.
Values are a 1.75 m adult (Winter, *Biomechanics and Motor Control of Human Movement*, segment
lengths as fractions of height: thigh 0.245 H, shank 0.246 H, foot 0.152 H, ankle height 0.039 H).
"""

from __future__ import annotations

HEIGHT_M = 1.75
THIGH_M = 0.43
"""Hip-joint centre to knee-joint centre."""
SHANK_M = 0.43
"""Knee-joint centre to ankle-joint centre."""
ANKLE_HEIGHT_M = 0.07
"""Ankle-joint centre above the floor when standing (the sole's thickness below it)."""
FOOT_M = 0.16
"""Ankle-joint centre to the toe joint (metatarsal heads), the thesis's ankle-toe line."""
FOOT_REST_DEG = -24.0
"""Foot angle (ankle -> toe joint, from the horizontal) when standing: the toe joint is lower than the ankle."""
HIP_HALF_WIDTH_M = 0.09
"""Lateral distance of each hip joint from the pelvis centre."""
STANDING_HIP_HEIGHT_M = THIGH_M + SHANK_M + ANKLE_HEIGHT_M
"""Hip-joint height above the floor with straight legs."""
