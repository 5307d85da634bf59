# Generates the meshes in this folder with gmsh's Python API (`pip install gmsh`).
# Exact command, run from the repository root:
#
#     python3 scenes/meshes/make_meshes.py
#
# It writes, as gmsh MSH 4.1 ASCII (the tetrahedra, or triangles in 2D, plus
# the boundary triangles, lines and points gmsh writes along, which elasto
# counts and ignores):
#   sphere.msh  - a ball of radius 0.5 centred at the origin
#   torus.msh   - a ring of radii 0.5 and 0.2 around the y axis, centred at the origin
#   bunny.msh   - a bunny-like blob (body, head, two ears, a tail), about
#                 1.2 x 1.2 x 0.76, sitting on y = 0, ears up (+y), head towards +x
#   annulus.msh - 2D: a disc of radius 0.5 with an off-centre hole of radius 0.2
# Meshing is deterministic for a given gmsh version (these were made with
# gmsh 4.15.2); the sizes keep each file well under 300 KB.

import os
import gmsh

HERE = os.path.dirname(os.path.abspath(__file__))


def finish(name, dimension, size):
    gmsh.model.occ.synchronize()
    gmsh.option.setNumber("Mesh.MeshSizeMin", size)
    gmsh.option.setNumber("Mesh.MeshSizeMax", size)
    gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
    gmsh.option.setNumber("Mesh.Optimize", 1)
    gmsh.model.mesh.generate(dimension)
    gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
    gmsh.option.setNumber("Mesh.Binary", 0)
    path = os.path.join(HERE, f"{name}.msh")
    gmsh.write(path)
    kept = 4 if dimension == 3 else 2
    _, tags, _ = gmsh.model.mesh.getElements(dimension)
    count = sum(len(t) for t in tags)
    nodes = len(gmsh.model.mesh.getNodes()[0])
    kind = "tetrahedra" if kept == 4 else "triangles"
    print(f"{name}.msh: {nodes} vertices, {count} {kind}, {os.path.getsize(path)} bytes")
    gmsh.model.remove()


gmsh.initialize()
gmsh.option.setNumber("General.Terminal", 0)
gmsh.option.setNumber("General.NumThreads", 1)
gmsh.option.setNumber("Mesh.RandomSeed", 1)

gmsh.model.add("sphere")
gmsh.model.occ.addSphere(0, 0, 0, 0.5)
finish("sphere", 3, 0.14)

gmsh.model.add("torus")
torus = gmsh.model.occ.addTorus(0, 0, 0, 0.5, 0.2)
# OCC's torus lies around the z axis: stand it around y (y is up in elasto).
gmsh.model.occ.rotate([(3, torus)], 0, 0, 0, 1, 0, 0, -3.141592653589793 / 2)
finish("torus", 3, 0.11)

gmsh.model.add("bunny")
occ = gmsh.model.occ
body = occ.addSphere(0, 0.38, 0, 1)
occ.dilate([(3, body)], 0, 0.38, 0, 0.45, 0.38, 0.38)
head = occ.addSphere(0.38, 0.72, 0, 0.24)
ears = []
for z in (-0.09, 0.09):
    ear = occ.addSphere(0.32, 1.0, z, 1)
    occ.dilate([(3, ear)], 0.32, 1.0, z, 0.06, 0.22, 0.09)
    ears.append(ear)
tail = occ.addSphere(-0.47, 0.45, 0, 0.1)
occ.fuse([(3, body)], [(3, head), (3, ears[0]), (3, ears[1]), (3, tail)])
finish("bunny", 3, 0.11)

gmsh.model.add("annulus")
disc = gmsh.model.occ.addDisk(0, 0, 0, 0.5, 0.5)
hole = gmsh.model.occ.addDisk(0.12, 0.05, 0, 0.2, 0.2)
gmsh.model.occ.cut([(2, disc)], [(2, hole)])
finish("annulus", 2, 0.07)

gmsh.finalize()
