"""Makes the small mesh fixtures of tests/mesh_import.rs.

Run from this folder (needs `pip install gmsh meshio`):

    python3 make_fixtures.py

The same unit cube (45 vertices, 100 tetrahedra, plus 84 boundary triangles,
24 lines and 8 points that elasto ignores) is written as gmsh MSH 2.2 and 4.1,
each ASCII and binary, as MEDIT, as TetGen .node/.ele (with every
tetrahedron in the other winding, as some tools write them) and as a
zlib-compressed binary VTU through meshio. The unit square (2D) is written as
MSH 4.1 and 2.2 ASCII and as Triangle .node/.ele. Every file is ours (made
here), under the repository's licence.
"""

import gmsh
import meshio
import numpy as np


def mesh_box(dimension, size):
    gmsh.model.add(f"box{dimension}")
    if dimension == 3:
        gmsh.model.occ.addBox(0, 0, 0, 1, 1, 1)
    else:
        gmsh.model.occ.addRectangle(0, 0, 0, 1, 1)
    gmsh.model.occ.synchronize()
    gmsh.model.mesh.setSize(gmsh.model.getEntities(0), size)
    gmsh.model.mesh.generate(dimension)


def save_msh(name, version, binary):
    gmsh.option.setNumber("Mesh.MshFileVersion", version)
    gmsh.option.setNumber("Mesh.Binary", 1 if binary else 0)
    gmsh.write(name)


def nodes_and(element_type):
    """Coordinates (n x 3) and 1-based connectivity of one element type."""
    tags, coords, _ = gmsh.model.mesh.getNodes()
    order = np.argsort(tags)
    assert (tags[order] == np.arange(1, len(tags) + 1)).all()
    coords = coords.reshape(-1, 3)[order]
    _, node_tags = gmsh.model.mesh.getElementsByType(element_type)
    nodes_per = {2: 3, 4: 4}[element_type]
    return coords, node_tags.reshape(-1, nodes_per).astype(np.int64)


def save_tetgen(stem, coords, simplices, dimension):
    """TetGen (3D) / Triangle (2D) files, numbered from 1, with one point
    attribute and boundary markers, one region attribute per element."""
    with open(f"{stem}.node", "w") as f:
        f.write(f"# {stem}.node: made by make_fixtures.py\n")
        f.write(f"{len(coords)} {dimension} 1 1\n")
        for i, p in enumerate(coords):
            xyz = " ".join(repr(float(c)) for c in p[:dimension])
            f.write(f"{i + 1} {xyz} 0.5 {int(i % 2)}\n")
    with open(f"{stem}.ele", "w") as f:
        f.write(f"{len(simplices)} {dimension + 1} 1\n")
        for i, s in enumerate(simplices):
            f.write(f"{i + 1} {' '.join(str(v) for v in s)} 7\n")
        f.write("# end of file\n")


gmsh.initialize()
gmsh.option.setNumber("General.Terminal", 0)

mesh_box(3, 0.6)
save_msh("cube_v2_ascii.msh", 2.2, False)
save_msh("cube_v2_binary.msh", 2.2, True)
save_msh("cube_v41_ascii.msh", 4.1, False)
save_msh("cube_v41_binary.msh", 4.1, True)
gmsh.write("cube.mesh")
coords, tets = nodes_and(4)
_, triangles = nodes_and(2)
# The other winding: swap the last two vertices of every tetrahedron.
save_tetgen("cube", coords, tets[:, [0, 1, 3, 2]], 3)
meshio.write(
    "cube.vtu",
    meshio.Mesh(coords, [("tetra", tets - 1), ("triangle", triangles - 1)]),
    binary=True,
    compression="zlib",
)
print(f"cube: {len(coords)} vertices, {len(tets)} tetrahedra, {len(triangles)} triangles")

mesh_box(2, 0.4)
save_msh("square_v41_ascii.msh", 4.1, False)
save_msh("square_v2_ascii.msh", 2.2, False)
coords, triangles = nodes_and(2)
save_tetgen("square", coords, triangles, 2)
print(f"square: {len(coords)} vertices, {len(triangles)} triangles")

gmsh.finalize()
