"""Time elasto and the tutorial on the 8_self_friction scene, alternately.

    python alternate.py TUTORIAL/8_self_friction ELASTO_BINARY ROUNDS OUT_DIR

Each round runs the tutorial (tutorial_run.py, 300 steps) and then elasto
(`run scenes/contact/self-friction-2d.toml --no-render`), one thread each
(OMP/OpenBLAS/RAYON_NUM_THREADS=1). Per step:
- the tutorial: wall and CPU time of its 300 step_forward calls
  (perf_counter, process_time), imports and set-up excluded;
- elasto: wall time of its 300 steps (the sum of stats.csv's sim_ms) and the
  CPU time of the whole process (user + sys from getrusage: start-up, scene
  and mesh reading and the writing of stats.csv included, so elasto's CPU per
  step is if anything overstated).
Prints every round, then the medians and the ratios tutorial / elasto.
Standard library only: run it with the venv's Python (the tutorial needs
numpy and scipy).
"""
import csv
import os
import resource
import statistics
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
SCENE = os.path.join(REPO, 'scenes', 'contact', 'self-friction-2d.toml')
STEPS = 300


def child_cpu():
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def run_tutorial(tutorial, out_dir, round_):
    out = os.path.join(out_dir, f'tutorial_{round_}.csv')
    line = subprocess.run(
        [sys.executable, os.path.join(HERE, 'tutorial_run.py'), tutorial, str(STEPS), out],
        check=True, capture_output=True, text=True).stdout.split()
    steps, wall, cpu, iterations = int(line[0]), float(line[1]), float(line[2]), int(line[3])
    return wall / steps * 1e3, cpu / steps * 1e3, iterations


def run_elasto(binary, out_dir, round_):
    out = os.path.join(out_dir, f'elasto_{round_}')
    before = child_cpu()
    subprocess.run([binary, 'run', SCENE, '--no-render', '--quiet', '--force', '--out', out],
                   check=True)
    cpu = child_cpu() - before
    rows = list(csv.DictReader(open(os.path.join(out, 'stats.csv'))))
    steps = round(float(rows[-1]['time']) / 0.01)
    assert steps == STEPS, f'elasto ran {steps} steps'
    wall = sum(float(r['sim_ms']) for r in rows)
    iterations = sum(int(r['newton_iters']) for r in rows)
    return wall / steps, cpu / steps * 1e3, iterations


def main():
    tutorial, binary, rounds, out_dir = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4]
    os.makedirs(out_dir, exist_ok=True)
    for name in ('OMP_NUM_THREADS', 'OPENBLAS_NUM_THREADS', 'MKL_NUM_THREADS', 'RAYON_NUM_THREADS'):
        os.environ[name] = '1'
    os.environ['SDL_VIDEODRIVER'] = 'dummy'
    results = {'tutorial': [], 'elasto': []}
    print('round  side      wall ms/step  cpu ms/step  Newton  load')
    for round_ in range(1, rounds + 1):
        for side, run in (('tutorial', lambda: run_tutorial(tutorial, out_dir, round_)),
                          ('elasto', lambda: run_elasto(binary, out_dir, round_))):
            wall, cpu, iterations = run()
            results[side].append((wall, cpu))
            print(f'{round_:5}  {side:8}  {wall:12.3f}  {cpu:11.3f}  {iterations:6}'
                  f'  {os.getloadavg()[0]:.2f}', flush=True)
    medians = {side: (statistics.median(w for w, _ in r), statistics.median(c for _, c in r))
               for side, r in results.items()}
    for side, (wall, cpu) in medians.items():
        print(f'median {side:8}  wall {wall:.3f} ms/step  cpu {cpu:.3f} ms/step')
    print(f"ratio tutorial / elasto: wall {medians['tutorial'][0] / medians['elasto'][0]:.0f}x,"
          f" cpu {medians['tutorial'][1] / medians['elasto'][1]:.0f}x")
    print(f'at {time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())}, load {os.getloadavg()}')


main()
