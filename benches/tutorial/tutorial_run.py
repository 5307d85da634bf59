"""Run the solid-sim tutorial's 8_self_friction headless and time its steps.

The scene set-up is simulator.py's, line for line, without pygame: the
tutorial's own time_integrator.step_forward does every step. Nothing here is
part of elasto; see README.md beside this file.

    python tutorial_run.py TUTORIAL/8_self_friction STEPS OUT.csv

OUT.csv has one row per step: step, wall_ms, cpu_ms, newton (iterations), the
centres of the two squares (the mean of their vertices, y shifted by +1 so
the ground is at y = 0 as in elasto's replica), the ceiling plate's height,
the top square's highest vertex and the bottom square's lowest (for the
contact times). With TUTORIAL_MASSES=lumped in the environment the squares get elasto's
lumped masses instead of the tutorial's equal ones (a check, not a timing).
The last line printed is `steps wall_s cpu_s iterations`.
"""
import os
import sys
import time

tutorial, steps, out = sys.argv[1], int(sys.argv[2]), sys.argv[3]
sys.path.insert(0, os.path.abspath(tutorial))

import numpy as np  # noqa: E402

import square_mesh  # noqa: E402
import time_integrator  # noqa: E402

# time_integrator prints every Newton iteration: count them instead.
iterations = [0]


def quiet_print(*args, **kwargs):
    if args and args[0] == 'Iteration':
        iterations[0] += 1


time_integrator.print = quiet_print

# simulation setup: simulator.py's, unchanged
side_len = 0.45
rho = 1000      # density of square
E = 1e5         # Young's modulus
nu = 0.4        # Poisson's ratio
n_seg = 2       # num of segments per side of the square
h = 0.01        # time step size in s
DBC = [(n_seg + 1) * (n_seg + 1) * 2]   # dirichlet node index
DBC_v = [np.array([0.0, -0.5])]         # dirichlet node velocity
DBC_limit = [np.array([0.0, -0.7])]     # dirichlet node limit position
ground_n = np.array([0.0, 1.0])         # normal of the slope
ground_n /= np.linalg.norm(ground_n)
ground_o = np.array([0.0, -1.0])        # a point on the slope
mu = 0.4        # friction coefficient of the slope

[x, e] = square_mesh.generate(side_len, n_seg)
e = np.append(e, np.array(e) + [len(x)] * 3, axis=0)
x = np.append(x, x + [side_len * 0.1, -side_len * 1.1], axis=0)
[bp, be] = square_mesh.find_boundary(e)
x = np.append(x, [[0.0, side_len * 0.6]], axis=0)
v = np.array([[0.0, 0.0]] * len(x))
m = [rho * side_len * side_len / ((n_seg + 1) * (n_seg + 1))] * len(x)
vol = [0.0] * len(e)
IB = [np.array([[0.0, 0.0]] * 2)] * len(e)
for i in range(0, len(e)):
    TB = [x[e[i][1]] - x[e[i][0]], x[e[i][2]] - x[e[i][0]]]
    vol[i] = np.linalg.det(np.transpose(TB)) / 2
    IB[i] = np.linalg.inv(np.transpose(TB))
mu_lame = [0.5 * E / (1 + nu)] * len(e)
lam = [E * nu / ((1 + nu) * (1 - 2 * nu))] * len(e)
is_DBC = [False] * len(x)
for i in DBC:
    is_DBC[i] = True
DBC_stiff = [1000]
contact_area = [side_len / n_seg] * len(x)
if os.environ.get('TUTORIAL_MASSES') == 'lumped':
    # Not the tutorial's: elasto's lumped masses (a third of each triangle's
    # mass to each of its vertices), to see how much of the trajectories'
    # difference the mass distribution makes. The ceiling node keeps its mass.
    m = [0.0] * (len(x) - 1) + [m[-1]]
    for i in range(0, len(e)):
        for j in e[i]:
            m[j] += rho * vol[i] / 3

per_square = (n_seg + 1) * (n_seg + 1)
rows = []
wall_total = cpu_total = 0.0
for step in range(1, steps + 1):
    before = iterations[0]
    w0, c0 = time.perf_counter(), time.process_time()
    [x, v] = time_integrator.step_forward(
        x, e, v, m, vol, IB, mu_lame, lam, ground_n, ground_o, bp, be, contact_area, mu,
        is_DBC, DBC, DBC_v, DBC_limit, DBC_stiff, h, 1e-2)
    w1, c1 = time.perf_counter(), time.process_time()
    wall_total += w1 - w0
    cpu_total += c1 - c0
    top = x[:per_square].mean(axis=0) + [0.0, 1.0]
    bottom = x[per_square:2 * per_square].mean(axis=0) + [0.0, 1.0]
    rows.append(f"{step},{(w1 - w0) * 1e3:.3f},{(c1 - c0) * 1e3:.3f},{iterations[0] - before},"
                f"{top[0]:.9f},{top[1]:.9f},{bottom[0]:.9f},{bottom[1]:.9f},{x[-1][1] + 1.0:.9f},"
                f"{x[:per_square, 1].max() + 1.0:.9f},{x[per_square:2 * per_square, 1].min() + 1.0:.9f}")

with open(out, 'w') as f:
    f.write("step,wall_ms,cpu_ms,newton,top_x,top_y,bottom_x,bottom_y,plate_y,top_max_y,bottom_min_y\n")
    f.write("\n".join(rows) + "\n")
print(steps, f"{wall_total:.4f}", f"{cpu_total:.4f}", iterations[0])
