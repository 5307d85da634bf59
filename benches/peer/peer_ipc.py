#!/usr/bin/env python3
"""The peer of elasto's contact benchmark: pbatoolkit + the IPC toolkit + CHOLMOD in a Newton loop.

A measurement script, not part of elasto (see README.md beside it). It reads what
`elasto run SCENE --save-meshes` wrote (the resolved `scene.toml` and `meshes/frame_0000.vtu`,
so the tetrahedra are elasto's own), and runs the same backward-Euler incremental potential:

    E(x) = 1/2 |x - x_pred|_M^2 + dt^2 (U_elastic + U_gravity + U_ground + U_contact)(x)

* U_elastic: pbatoolkit's stable Neo-Hookean kernels (one-point quadrature on linear
  tetrahedra), with pbatoolkit's lambda set to elasto's lambda' = lambda + mu, which makes
  pbatoolkit's mu/2 (I_C - 3) + lambda'/2 (J - 1 - mu/lambda')^2 elasto's energy plus a constant;
  element Hessians projected to PSD by pbatoolkit (HyperElasticSpdCorrection.Projection);
* U_contact: the IPC toolkit's BarrierPotential (kappa sum b(d^2, d_hat^2), the original IPC
  collision set, no area weighting, edge-edge mollifier), its Hessian clamped to PSD per stencil,
  its broad phase for the active set at each iterate and the candidates of each line-search
  segment, and its additive CCD (conservative rescaling 0.9) for the largest safe step;
* U_ground: elasto's ground barrier kappa_g sum b(y - h; a) written here in numpy (a vertex
  against a plane; the IPC toolkit's plane barrier works on squared distances with the contact
  kappa, which is not elasto's ground term); its step cap closes at most 90% of any gap;
* lumped masses rho V_e / 4 per vertex, as elasto's;
* the linear solve: CHOLMOD (scikit-sparse) supernodal Cholesky of the lower triangle, the
  symbolic analysis redone only when the Hessian's pattern grows (the union of every pattern
  seen, as elasto keeps its own);
* elasto's Newton loop (src/solver/newton.rs): the step starts at min(1, the caps), Armijo
  backtracking (c = 1e-4, round-off slack 1e-13 |E|, at most 60 halvings), and the step stops
  when max|dx| / dt < tolerance, tested after the line search.

Usage (see README.md):
    peer_ipc.py run ELASTO_OUT PEER_OUT [--frames N] [--threads 1]
    peer_ipc.py compare ELASTO_OUT PEER_OUT
    peer_ipc.py check
"""

import argparse
import csv
import os
import sys
import time
import tomllib

import numpy as np


def parse_args():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    sub = parser.add_subparsers(dest="command", required=True)
    run = sub.add_parser("run", help="simulate the scene elasto ran, write PEER_OUT")
    run.add_argument("elasto_out", help="an `elasto run --save-meshes` output folder")
    run.add_argument("peer_out", help="folder for stats.csv and positions.npz")
    run.add_argument("--frames", type=int, help="frames to run (default: the scene's)")
    run.add_argument(
        "--threads", type=int, default=1, help="threads for TBB, OpenMP and BLAS (default 1)"
    )
    run.add_argument(
        "--broad-phase",
        default="hash-grid",
        choices=["hash-grid", "lbvh", "sweep-and-prune", "brute-force"],
        help="the IPC toolkit's broad phase (default hash-grid)",
    )
    compare = sub.add_parser("compare", help="compare a peer run with elasto's")
    compare.add_argument("elasto_out")
    compare.add_argument("peer_out")
    sub.add_parser("check", help="check the peer's energies against elasto's formulas")
    totals = sub.add_parser("summary", help="the medians of alternate.sh's runs")
    totals.add_argument("out", help="alternate.sh's output folder")
    return parser.parse_args()


def limit_threads(threads):
    """One thread for every library: OpenMP and OpenBLAS by environment (before they load);
    TBB, linked statically into pbatoolkit and the IPC toolkit, sizes its arena from the CPU
    affinity when it first runs, so the process is pinned while the arenas are made."""
    for var in ["OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"]:
        os.environ[var] = str(threads)
    allowed = os.sched_getaffinity(0)
    if threads < len(allowed):
        os.sched_setaffinity(0, sorted(allowed)[:threads])
    return allowed


# ---------------------------------------------------------------------------------------------
# The terms


def clamped_log_barrier(d, a):
    """b(d) = -(d - a)^2 ln(d / a) on (0, a), 0 beyond, +inf at or below 0; with b', b''."""
    b = np.zeros_like(d)
    db = np.zeros_like(d)
    ddb = np.zeros_like(d)
    inside = (d > 0) & (d < a)
    di = d[inside]
    log = np.log(di / a)
    b[inside] = -((di - a) ** 2) * log
    db[inside] = -2 * (di - a) * log - (di - a) ** 2 / di
    ddb[inside] = -2 * log - 4 * (di - a) / di + (di - a) ** 2 / di**2
    b[d <= 0] = np.inf
    return b, db, ddb


def boundary_faces(tets):
    """The triangles that belong to one tetrahedron only."""
    faces = np.concatenate(
        [tets[:, [0, 1, 2]], tets[:, [0, 1, 3]], tets[:, [0, 2, 3]], tets[:, [1, 2, 3]]]
    )
    keys = np.sort(faces, axis=1)
    _, index, count = np.unique(keys, axis=0, return_index=True, return_counts=True)
    return faces[index[count == 1]]


class Scene:
    """What the peer needs from elasto's output folder."""

    def __init__(self, elasto_out):
        import meshio

        with open(os.path.join(elasto_out, "scene.toml"), "rb") as f:
            scene = tomllib.load(f)
        self.raw = scene
        if scene.get("dimension") != 3:
            sys.exit("peer: only 3D scenes")
        timing = scene["time"]
        if timing.get("integrator", "backward-euler") != "backward-euler":
            sys.exit("peer: only time.integrator = backward-euler")
        self.dt = 1.0 / (timing["fps"] * timing["substeps"])
        self.substeps = timing["substeps"]
        self.frames = timing["frames"]
        solver = scene["solver"]
        if solver.get("method", "newton") != "newton":
            sys.exit("peer: only solver.method = newton")
        self.tolerance = solver["tolerance"]
        self.max_iterations = solver["max_iterations"]
        effects = scene.get("effects", {})
        if "pinned" in effects:
            sys.exit("peer: no pinned vertices")
        self.gravity = np.array(effects.get("gravity", {}).get("acceleration", [0, 0, 0]), float)
        ground = effects.get("ground")
        self.ground = None
        if ground is not None:
            if "kappa" not in ground:
                sys.exit("peer: give [effects.ground] kappa in the scene")
            self.ground = (ground["height"], ground["a"], ground["kappa"])
        contact = effects.get("contact")
        if contact is None or "kappa" not in contact:
            sys.exit("peer: the scene needs [effects.contact] with a fixed kappa")
        if not contact.get("self", True):
            sys.exit("peer: only self = true (every pair of surface primitives collides)")
        if contact.get("friction", 0) or (ground or {}).get("friction", 0):
            sys.exit("peer: no friction")
        self.d_hat = contact["distance"]
        self.kappa = contact["kappa"]

        mesh = meshio.read(os.path.join(elasto_out, "meshes", "frame_0000.vtu"))
        self.x0 = np.ascontiguousarray(mesh.points, dtype=float)
        self.tets = np.ascontiguousarray(mesh.cells_dict["tetra"], dtype=np.int64)
        bodies = scene["bodies"]
        body_of_vertex = self.vertex_bodies(len(bodies))
        body_of_tet = body_of_vertex[self.tets[:, 0]]
        self.mu = np.empty(len(self.tets))
        self.lam = np.empty(len(self.tets))
        self.rho = np.empty(len(self.tets))
        self.v0 = np.zeros_like(self.x0)
        for b, body in enumerate(bodies):
            material = body["material"]
            if material["model"] != "stable-neo-hookean":
                sys.exit("peer: only model = stable-neo-hookean (the law pbatoolkit has)")
            if "young" in material:
                e, nu = material["young"], material["poisson"]
                mu, lam = e / (2 * (1 + nu)), e * nu / ((1 + nu) * (1 - 2 * nu))
            else:
                mu, lam = material["mu"], material["lambda"]
            self.mu[body_of_tet == b] = mu
            self.lam[body_of_tet == b] = lam
            self.rho[body_of_tet == b] = material["density"]
            if "pinned" in body:
                sys.exit("peer: no pinned vertices")
            self.v0[body_of_vertex == b] = body["mesh"].get("velocity", [0.0, 0.0, 0.0])
        d = self.x0[self.tets[:, 1:]] - self.x0[self.tets[:, [0]]]
        self.volumes = np.abs(np.linalg.det(d)) / 6
        self.masses = np.zeros(len(self.x0))
        np.add.at(self.masses, self.tets.ravel(), np.repeat(self.rho * self.volumes / 4, 4))
        self.faces = boundary_faces(self.tets)

    def vertex_bodies(self, count):
        """Bodies are the connected components of the mesh, in elasto's order (by first vertex)."""
        import scipy.sparse as sp
        from scipy.sparse.csgraph import connected_components

        n = len(self.x0)
        rows = np.repeat(self.tets[:, 0], 3)
        cols = self.tets[:, 1:].ravel()
        graph = sp.coo_matrix((np.ones(len(rows)), (rows, cols)), shape=(n, n))
        found, labels = connected_components(graph, directed=False)
        if found != count:
            sys.exit(f"peer: {found} connected pieces for {count} bodies")
        first = np.full(found, n)
        np.minimum.at(first, labels, np.arange(n))
        order = np.argsort(np.argsort(first))
        return order[labels]


class PatternedCholesky:
    """CHOLMOD on the lower triangle; symbolic analysis only when a new entry appears."""

    def __init__(self, n):
        self.n = n
        self.keys = np.empty(0, dtype=np.int64)
        self.factor = None
        self.reanalyses = 0

    def place(self, lower):
        """`lower` on the union of the patterns seen so far (grown, and analysed again, when it
        has an entry the union lacks); returns the matrix and whether it was analysed."""
        import scipy.sparse as sp
        from sksparse.cholmod import analyze

        lower.sum_duplicates()
        lower.sort_indices()
        cols = np.repeat(np.arange(self.n, dtype=np.int64), np.diff(lower.indptr))
        keys = cols * self.n + lower.indices
        pos = np.searchsorted(self.keys, keys)
        known = len(self.keys) > 0 and np.all(
            self.keys[np.minimum(pos, len(self.keys) - 1)] == keys
        )
        if not known:
            self.keys = np.union1d(self.keys, keys)
            self.rows = (self.keys % self.n).astype(np.int32)
            self.indptr = np.searchsorted(
                self.keys // self.n, np.arange(self.n + 1, dtype=np.int64)
            ).astype(np.int32)
            pos = np.searchsorted(self.keys, keys)
        data = np.zeros(len(self.keys))
        data[pos] = lower.data
        matrix = sp.csc_matrix((data, self.rows, self.indptr), shape=(self.n, self.n))
        if not known:
            self.factor = analyze(matrix, mode="supernodal")
            self.reanalyses += 1
        return matrix, not known

    def factorise(self, matrix):
        """The numeric factorisation of a matrix `place` returned."""
        self.factor.cholesky_inplace(matrix)

    def solve(self, rhs):
        return self.factor.solve_A(rhs)


class Peer:
    """The incremental potential of one backward-Euler step and its Newton loop."""

    def __init__(self, scene, broad_phase):
        import ipctk
        import pbatoolkit as pbat

        self.pbat = pbat.pbat.fem
        self.ipctk = ipctk
        self.scene = scene
        self.n = len(scene.x0)
        tets = scene.tets
        self.E = np.asfortranarray(tets.T)
        X = np.asfortranarray(scene.x0.T)
        element = self.pbat.Element.Tetrahedron
        self.element = element
        self.GNe = self.pbat.shape_function_gradients(
            self.E, X, element=element, order=1, dims=3, quadrature_order=1
        )
        wg = self.pbat.mesh_quadrature_weights(self.E, X, element, order=1, quadrature_order=1)
        self.eg = np.ravel(self.pbat.mesh_quadrature_elements(self.E, wg))
        # One point per tetrahedron; its weight is the element's volume. pbatoolkit's own
        # weights carry its rule's 0.166667 for 1/6 (2e-6 too large), so the exact volumes
        # are given instead, as elasto has them.
        if not np.allclose(np.ravel(wg), scene.volumes[self.eg], rtol=1e-5):
            sys.exit("peer: pbatoolkit's quadrature points are not one per element")
        self.wg = scene.volumes[self.eg]
        self.mug = scene.mu[self.eg]
        # pbatoolkit's lambda is elasto's lambda' = lambda + mu (see the module doc).
        self.lambdag = (scene.lam + scene.mu)[self.eg]
        # Its energy exceeds elasto's by mu^2 / (2 lambda') per unit volume.
        self.elastic_offset = float(np.sum(self.wg * self.mug**2 / (2 * self.lambdag)))

        edges = ipctk.edges(np.asfortranarray(scene.faces.astype(np.int32)))
        self.mesh = ipctk.CollisionMesh.build_from_full_mesh(
            np.asfortranarray(scene.x0), edges, np.asfortranarray(scene.faces.astype(np.int32))
        )
        self.broad_phase = {
            "hash-grid": ipctk.HashGrid,
            "lbvh": ipctk.LBVH,
            "sweep-and-prune": ipctk.SweepAndPrune,
            "brute-force": ipctk.BruteForce,
        }[broad_phase]()
        self.barrier = ipctk.BarrierPotential(scene.d_hat, scene.kappa)
        self.ccd = ipctk.AdditiveCCD()
        self.collisions = ipctk.NormalCollisions()
        self.candidates = ipctk.Candidates()
        self.cholesky = PatternedCholesky(3 * self.n)
        self.masses3 = np.repeat(scene.masses, 3)
        self.gravity_force = (scene.masses[:, None] * scene.gravity[None, :]).ravel()
        self.timers = {}

    # --- timing -------------------------------------------------------------------------------
    def tic(self):
        return time.perf_counter()

    def toc(self, name, start):
        self.timers[name] = self.timers.get(name, 0.0) + time.perf_counter() - start

    # --- energies -----------------------------------------------------------------------------
    def elastic(self, x, flags):
        f = self.pbat.ElementElasticityComputationFlags
        bits = 0
        for name in flags:
            bits |= int(getattr(f, name))
        return self.pbat.hyper_elastic_potential(
            self.E,
            self.n,
            eg=self.eg,
            wg=self.wg,
            GNeg=self.GNe,
            mug=self.mug,
            lambdag=self.lambdag,
            x=x,
            energy=self.pbat.HyperElasticEnergy.StableNeoHookean,
            flags=bits,
            spd_correction=self.pbat.HyperElasticSpdCorrection.Projection,
            element=self.element,
            order=1,
            dims=3,
        )

    def ground(self, x):
        if self.scene.ground is None:
            z = np.zeros(self.n)
            return 0.0, z, z
        height, a, kappa = self.scene.ground
        b, db, ddb = clamped_log_barrier(x[1::3] - height, a)
        return kappa * b.sum(), kappa * db, kappa * ddb

    def energy(self, x, x_pred, collisions_at_x=True):
        """E(x); the contact term over `self.collisions`, built at x from the candidates."""
        dt2 = self.scene.dt**2
        start = self.tic()
        u_el = self.elastic(x, ["Potential"])[0] - self.elastic_offset
        self.toc("energy_elastic", start)
        start = self.tic()
        vc = self.mesh.vertices(x.reshape(-1, 3))
        if collisions_at_x:
            self.collisions.build(self.candidates, self.mesh, vc, self.scene.d_hat)
        self.toc("line_search_collisions", start)
        start = self.tic()
        u_c = self.barrier(self.collisions, self.mesh, vc)
        self.toc("energy_contact", start)
        u_g = self.ground(x)[0]
        dx = x - x_pred
        inertia = 0.5 * np.dot(self.masses3 * dx, dx)
        return inertia + dt2 * (u_el - np.dot(self.gravity_force, x) + u_g + u_c)

    # --- one step -----------------------------------------------------------------------------
    def step(self, x, v, stats):
        scene = self.scene
        dt, dt2 = scene.dt, scene.dt**2
        x_pred = x + dt * v
        x_start = x.copy()
        x = x.copy()
        # The collisions at the starting point (candidates from a zero-length segment).
        start = self.tic()
        xc = self.mesh.vertices(x.reshape(-1, 3))
        self.candidates.build(self.mesh, xc, scene.d_hat / 2, self.broad_phase)
        self.toc("broad_phase", start)
        energy = self.energy(x, x_pred)
        iterations = 0
        while iterations < scene.max_iterations:
            iterations += 1
            # Assembly: the active set at x, then gradient and projected Hessian.
            t_assembly = self.tic()
            start = self.tic()
            xc = self.mesh.vertices(x.reshape(-1, 3))
            self.collisions.build(self.mesh, xc, scene.d_hat, 0.0, self.broad_phase)
            self.toc("broad_phase", start)
            start = self.tic()
            _, g_el, h_el = self.elastic(x, ["Gradient", "Hessian"])
            self.toc("elastic_derivatives", start)
            start = self.tic()
            g_c = self.mesh.to_full_dof(self.barrier.gradient(self.collisions, self.mesh, xc))
            h_c = self.mesh.to_full_dof(
                self.barrier.hessian(
                    self.collisions, self.mesh, xc, self.ipctk.PSDProjectionMethod.CLAMP
                )
            )
            self.toc("contact_derivatives", start)
            start = self.tic()
            _, g_g, h_g = self.ground(x)
            gradient = self.masses3 * (x - x_pred) + dt2 * (g_el + g_c - self.gravity_force)
            gradient[1::3] += dt2 * g_g
            diagonal = self.masses3.copy()
            diagonal[1::3] += dt2 * h_g
            import scipy.sparse as sp

            hessian = (h_el.tocsc() + h_c) * dt2 + sp.diags(diagonal, format="csc")
            lower = sp.tril(hessian, format="csc")
            # Onto the grown pattern; analysed again when it grew (as elasto's assembly does).
            matrix, analysed = self.cholesky.place(lower)
            stats["reanalyses"] += int(analysed)
            self.toc("sum_and_pattern", start)
            self.toc("assembly", t_assembly)
            start = self.tic()
            self.cholesky.factorise(matrix)
            self.toc("factorisation", start)
            start = self.tic()
            direction = self.cholesky.solve(-gradient)
            self.toc("solve", start)
            residual = np.max(np.abs(direction)) / dt
            # Line search.
            t_line = self.tic()
            slope = float(np.dot(gradient, direction))
            t = 1.0
            down = direction[1::3] < 0
            if scene.ground is not None and np.any(down):
                gap = x[1::3][down] - scene.ground[0]
                t = min(t, float(np.min(0.9 * gap / -direction[1::3][down])))
            start = self.tic()
            xc1 = self.mesh.vertices((x + direction).reshape(-1, 3))
            self.candidates.build(self.mesh, xc, xc1, scene.d_hat / 2, self.broad_phase)
            self.toc("broad_phase", start)
            start = self.tic()
            t = min(
                t,
                self.candidates.compute_collision_free_stepsize(
                    self.mesh, xc, xc1, 0.0, self.ccd
                ),
            )
            self.toc("ccd", start)
            accepted = False
            backtracks = 61 if t > 0 else 0
            for _ in range(backtracks):
                trial = x + t * direction
                trial_energy = self.energy(trial, x_pred)
                if trial_energy <= energy + 1e-4 * t * slope + 1e-13 * abs(energy):
                    x, energy, accepted = trial, trial_energy, True
                    break
                t *= 0.5
                stats["backtracks"] += 1
            self.toc("line_search", t_line)
            if residual < scene.tolerance:
                break
            if not accepted:
                stats["stalled_steps"] += 1
                break
        else:
            stats["unconverged_steps"] += 1
        stats["newton_iters"] += iterations
        stats["contact_pairs"] = len(self.collisions)
        return x, (x - x_start) / dt


def run(args):
    allowed = limit_threads(args.threads)
    import ipctk

    ipctk.set_num_threads(args.threads)
    scene = Scene(args.elasto_out)
    peer = Peer(scene, args.broad_phase)
    # Let TBB make its arenas under the pinned affinity, then give the process its cores back
    # (one thread may then run on either).
    x = scene.x0.ravel().copy()
    peer.elastic(x, ["Potential", "Gradient", "Hessian"])
    xc = peer.mesh.vertices(scene.x0)
    peer.collisions.build(peer.mesh, xc, scene.d_hat, 0.0, peer.broad_phase)
    os.sched_setaffinity(0, allowed)

    frames = args.frames if args.frames is not None else scene.frames
    os.makedirs(args.peer_out, exist_ok=True)
    v = scene.v0.ravel().copy()
    positions = [x.reshape(-1, 3).copy()]
    columns = [
        "frame", "newton_iters", "backtracks", "unconverged_steps", "stalled_steps",
        "reanalyses", "contact_pairs", "sim_ms", "cpu_ms", "assembly_ms", "factorisation_ms",
        "solve_ms", "line_search_ms", "broad_phase_ms", "ccd_ms", "contact_derivatives_ms",
        "elastic_derivatives_ms", "energy_elastic_ms", "energy_contact_ms",
        "line_search_collisions_ms", "sum_and_pattern_ms",
    ]  # fmt: skip
    rows = []
    for frame in range(1, frames):
        stats = dict.fromkeys(["newton_iters", "backtracks", "unconverged_steps"], 0)
        stats.update(stalled_steps=0, reanalyses=0, contact_pairs=0)
        peer.timers = {}
        wall, cpu = time.perf_counter(), time.process_time()
        for _ in range(scene.substeps):
            x, v = peer.step(x, v, stats)
        stats["sim_ms"] = 1e3 * (time.perf_counter() - wall)
        stats["cpu_ms"] = 1e3 * (time.process_time() - cpu)
        for name in columns:
            if name.endswith("_ms") and name not in ("sim_ms", "cpu_ms"):
                stats[name] = 1e3 * peer.timers.get(name[:-3], 0.0)
        rows.append([frame] + [stats[c] for c in columns[1:]])
        positions.append(x.reshape(-1, 3).copy())
        print(
            f"frame {frame}: {stats['newton_iters']} iterations, {stats['sim_ms']:.0f} ms",
            file=sys.stderr,
        )
    with open(os.path.join(args.peer_out, "stats.csv"), "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(columns)
        writer.writerows(rows)
    np.savez_compressed(os.path.join(args.peer_out, "positions.npz"), x=np.array(positions))


def compare(args):
    import meshio

    scene = Scene(args.elasto_out)
    peer = np.load(os.path.join(args.peer_out, "positions.npz"))["x"]
    body = Scene.vertex_bodies(scene, len(scene.raw["bodies"]))
    with open(os.path.join(args.elasto_out, "stats.csv")) as f:
        elasto_rows = list(csv.DictReader(f))
    with open(os.path.join(args.peer_out, "stats.csv")) as f:
        peer_rows = list(csv.DictReader(f))
    print("frame | elasto its | peer its | max vertex distance | max body COM distance")
    worst = 0.0
    for frame in range(1, len(peer)):
        path = os.path.join(args.elasto_out, "meshes", f"frame_{frame:04}.vtu")
        x_elasto = meshio.read(path).points
        x_peer = peer[frame]
        distance = np.linalg.norm(x_elasto - x_peer, axis=1).max()
        com = 0.0
        for b in range(body.max() + 1):
            m = scene.masses[body == b]
            c_e = (m[:, None] * x_elasto[body == b]).sum(0) / m.sum()
            c_p = (m[:, None] * x_peer[body == b]).sum(0) / m.sum()
            com = max(com, np.linalg.norm(c_e - c_p))
        worst = max(worst, distance)
        print(
            f"{frame} | {elasto_rows[frame]['newton_iters']} | {peer_rows[frame - 1]['newton_iters']}"
            f" | {distance:.3e} | {com:.3e}"
        )
    print(f"largest vertex distance over the frames: {worst:.3e}")


PHASES = ["assembly_ms", "factorisation_ms", "solve_ms", "line_search_ms", "broad_phase_ms", "ccd_ms"]


def read_run(folder):
    """Totals of one run's stats.csv (elasto's or the peer's) and its `time` file's CPU seconds."""
    with open(os.path.join(folder, "stats.csv")) as f:
        rows = [r for r in csv.DictReader(f) if int(r["frame"]) > 0]
    columns = ["sim_ms", "newton_iters", "elastic_derivatives_ms", "contact_derivatives_ms",
               "sum_and_pattern_ms"] + PHASES  # fmt: skip
    total = {c: sum(float(r[c]) for r in rows) for c in columns if c in rows[0]}
    total["frames"] = len(rows)
    time_file = folder + ".time"
    if os.path.exists(time_file):
        wall, user, system = (float(v) for v in open(time_file).read().split()[-3:])
        total["process_wall_s"], total["process_cpu_s"] = wall, user + system
    return total


def summary(args):
    """Medians over the runs of `alternate.sh`: per step, per Newton iteration, the phase split."""
    with open(os.path.join(args.out, "reference", "scene.toml"), "rb") as f:
        substeps = tomllib.load(f)["time"]["substeps"]
    sides = {}
    for side in ["elasto", "peer"]:
        runs = sorted(d for d in os.listdir(args.out) if d.startswith(side + "-") and "." not in d)
        sides[side] = [read_run(os.path.join(args.out, d)) for d in runs]

    def median(side, key):
        values = sorted(run[key] for run in sides[side] if key in run)
        return values[len(values) // 2] if values else float("nan")

    print(f"runs: elasto {len(sides['elasto'])}, peer {len(sides['peer'])} (medians)")
    print("| | elasto | peer | peer / elasto |")
    print("|---|--:|--:|--:|")
    lines = []
    for side in sides:
        steps = median(side, "frames") * substeps
        iterations = median(side, "newton_iters")
        line = {
            "ms per step": median(side, "sim_ms") / steps,
            "Newton iterations per step": iterations / steps,
            "ms per Newton iteration": median(side, "sim_ms") / iterations,
            "process wall s": median(side, "process_wall_s"),
            "process CPU s": median(side, "process_cpu_s"),
        }
        for phase in PHASES:
            line[f"{phase[:-3]} ms per iteration (share of the step)"] = (
                median(side, phase) / iterations,
                median(side, phase) / median(side, "sim_ms"),
            )
        lines.append(line)
    for key in lines[0]:
        e, p = lines[0][key], lines[1][key]
        if isinstance(e, tuple):
            print(f"| {key} | {e[0]:.3g} ({100 * e[1]:.0f}%) | {p[0]:.3g} ({100 * p[1]:.0f}%)"
                  f" | {p[0] / e[0]:.2f} |")
        else:
            print(f"| {key} | {e:.3g} | {p:.3g} | {p / e:.2f} |")
    peer_parts = ["elastic_derivatives_ms", "contact_derivatives_ms", "sum_and_pattern_ms"]
    runs = sides["peer"]
    if runs and all(part in runs[0] for part in peer_parts):
        iterations = median("peer", "newton_iters")
        parts = ", ".join(f"{p[:-3]} {median('peer', p) / iterations:.3g}" for p in peer_parts)
        print(f"peer's assembly, ms per iteration: {parts}")


def check():
    """The peer's terms against elasto's formulas at random states (no elasto run needed)."""
    import ipctk
    import pbatoolkit as pbat

    rng = np.random.default_rng(1)
    fem = pbat.pbat.fem
    # One tetrahedron: pbatoolkit's SNH with lambda' against elasto's formula.
    X = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float) * 0.1
    E = np.asfortranarray(np.array([[0, 1, 2, 3]]).T)
    element = fem.Element.Tetrahedron
    XT = np.asfortranarray(X.T)
    GNe = fem.shape_function_gradients(E, XT, element=element, order=1, dims=3, quadrature_order=1)
    wg = np.ravel(fem.mesh_quadrature_weights(E, XT, element, order=1, quadrature_order=1))
    eg = np.ravel(fem.mesh_quadrature_elements(E, wg.reshape(1, -1)))
    volume = 0.1**3 / 6
    wg = np.array([volume])
    mu, lam = 769.2, 1153.8
    x = (X + 0.02 * rng.standard_normal(X.shape)).ravel()
    u = fem.hyper_elastic_potential(
        E, 4, eg=eg, wg=wg, GNeg=GNe, mug=np.array([mu]), lambdag=np.array([lam + mu]), x=x,
        energy=fem.HyperElasticEnergy.StableNeoHookean,
        flags=int(fem.ElementElasticityComputationFlags.Potential),
        spd_correction=fem.HyperElasticSpdCorrection.NoCorrection, element=element,
    )[0]  # fmt: skip
    F = (x.reshape(4, 3)[1:] - x.reshape(4, 3)[0]).T @ np.linalg.inv((X[1:] - X[0]).T)
    J = np.linalg.det(F)
    lp = lam + mu
    psi = mu / 2 * (np.sum(F * F) - 3) - mu * (J - 1) + lp / 2 * (J - 1) ** 2
    expected = volume * (psi + mu**2 / (2 * lp))
    print(f"elastic: pbatoolkit {u:.15e}, elasto's formula + offset {expected:.15e}")
    assert abs(u - expected) <= 1e-12 * abs(expected)
    # Two triangles 3e-3 apart, d_hat 5e-3: three point-triangle stencils.
    V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0.2, 0.2, 3e-3], [0.3, 0.2, 3e-3],
                  [0.2, 0.3, 3e-3]], float)  # fmt: skip
    F3 = np.array([[0, 1, 2], [3, 4, 5]], dtype=np.int32)
    mesh = ipctk.CollisionMesh(V, ipctk.edges(F3), F3)
    collisions = ipctk.NormalCollisions()
    collisions.build(mesh, V, 5e-3)
    kappa = 7.0
    value = ipctk.BarrierPotential(5e-3, kappa)(collisions, mesh, V)
    s, s_hat = (3e-3) ** 2, (5e-3) ** 2
    expected = kappa * 3 * -((s - s_hat) ** 2) * np.log(s / s_hat)
    print(f"contact: ipctk {value:.15e}, kappa sum b(d^2, d_hat^2) {expected:.15e}")
    assert abs(value - expected) <= 1e-12 * expected
    print("ok")


def main():
    args = parse_args()
    if args.command == "run":
        run(args)
    elif args.command == "compare":
        compare(args)
    elif args.command == "summary":
        summary(args)
    else:
        check()


if __name__ == "__main__":
    main()
