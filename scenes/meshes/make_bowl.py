# Writes bowl.obj: an open hemispherical bowl, the inside of a sphere of
# radius 1 below its centre (y <= 0), centre at the origin, rim at y = 0,
# bottom at y = -1; 12 rings of 32 segments (a fan at the bottom). Plain
# Python, no packages. Exact command, from the repository root:
#
#     python3 scenes/meshes/make_bowl.py
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))
RINGS, SEGMENTS = 12, 32

points = [(0.0, -1.0, 0.0)]  # the bottom
for ring in range(1, RINGS + 1):
    polar = (math.pi / 2) * ring / RINGS  # from the bottom (0) to the rim (pi/2)
    y, r = -math.cos(polar), math.sin(polar)
    for k in range(SEGMENTS):
        azimuth = 2 * math.pi * k / SEGMENTS
        points.append((r * math.cos(azimuth), y, r * math.sin(azimuth)))


def index(ring, k):
    """1-based OBJ index of point k of ring `ring` (1..RINGS)."""
    return 2 + (ring - 1) * SEGMENTS + k % SEGMENTS


faces = [(1, index(1, k + 1), index(1, k)) for k in range(SEGMENTS)]
for ring in range(1, RINGS):
    for k in range(SEGMENTS):
        a, b = index(ring, k), index(ring, k + 1)
        c, d = index(ring + 1, k), index(ring + 1, k + 1)
        faces += [(a, b, d), (a, d, c)]

with open(os.path.join(HERE, "bowl.obj"), "w") as out:
    out.write("# An open hemispherical bowl of radius 1, rim at y = 0 (make_bowl.py)\n")
    for p in points:
        out.write("v {:.9g} {:.9g} {:.9g}\n".format(*p))
    for f in faces:
        out.write("f {} {} {}\n".format(*f))
