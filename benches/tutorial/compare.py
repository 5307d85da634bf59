"""Hold elasto's self-friction-2d trajectory against the tutorial's.

    python compare.py TUTORIAL.csv ELASTO_OUT

TUTORIAL.csv is tutorial_run.py's output (one row per step, dt = 0.01 s);
ELASTO_OUT is an `elasto run contact/self-friction-2d.toml --save-meshes`
folder (one VTU per frame; run it with `--set time.fps=100 --set
time.substeps=1 --frames 300` for a frame every step of dt = 0.01 s). Prints both squares' centres every
0.2 s, the largest differences over all frames, and when each run's top
square first has the plate within d_hat (the squeeze begins) and when the
bottom square first comes within d_hat of the ground. Plain Python: no numpy.
"""
import csv
import os
import re
import sys

DT = 0.01
D_HAT = 0.01
PER_SQUARE = 9


def elasto_frames(out):
    frames = {}
    folder = os.path.join(out, 'meshes')
    for name in sorted(os.listdir(folder)):
        match = re.fullmatch(r'frame_(\d+)\.vtu', name)
        if not match:
            continue
        text = open(os.path.join(folder, name)).read()
        block = text.split('<Points>')[1].split('>', 2)[1].split('<')[0]
        values = [float(v) for v in block.split()]
        points = [(values[i], values[i + 1]) for i in range(0, len(values), 3)]
        frames[int(match.group(1))] = points
    return frames


def steps_per_frame(out):
    # the run's resolved scene.toml holds `substeps = N` under [time]
    for line in open(os.path.join(out, 'scene.toml')):
        match = re.match(r'\s*substeps\s*=\s*(\d+)', line)
        if match:
            return int(match.group(1))
    return 1


def centre(points):
    return (sum(p[0] for p in points) / len(points), sum(p[1] for p in points) / len(points))


def main():
    tutorial_csv, out = sys.argv[1], sys.argv[2]
    steps_per = steps_per_frame(out)
    rows = {int(r['step']): r for r in csv.DictReader(open(tutorial_csv))}
    frames = elasto_frames(out)
    worst = {'top_x': 0.0, 'top_y': 0.0, 'bottom_x': 0.0, 'bottom_y': 0.0}
    first = {}
    print(f"{'t':>5} {'top y tut':>10} {'elasto':>10} {'bottom y tut':>12} {'elasto':>10}"
          f" {'top x tut':>10} {'elasto':>10} {'bottom x tut':>12} {'elasto':>10}")
    for frame in sorted(frames):
        step = frame * steps_per
        points = frames[frame]
        top, bottom = centre(points[:PER_SQUARE]), centre(points[PER_SQUARE:2 * PER_SQUARE])
        t = step * DT
        plate = max(1.27 - 0.5 * t, 0.3)
        if plate - max(p[1] for p in points[:PER_SQUARE]) < D_HAT:
            first.setdefault('elasto plate', t)
        if min(p[1] for p in points[PER_SQUARE:2 * PER_SQUARE]) < D_HAT:
            first.setdefault('elasto ground', t)
        if step not in rows:
            continue
        r = rows[step]
        theirs = {k: float(r[k]) for k in worst}
        ours = {'top_x': top[0], 'top_y': top[1], 'bottom_x': bottom[0], 'bottom_y': bottom[1]}
        for k in worst:
            worst[k] = max(worst[k], abs(theirs[k] - ours[k]))
        if step % 20 == 0:
            print(f"{t:5.2f} {theirs['top_y']:10.5f} {ours['top_y']:10.5f} {theirs['bottom_y']:12.5f}"
                  f" {ours['bottom_y']:10.5f} {theirs['top_x']:10.5f} {ours['top_x']:10.5f}"
                  f" {theirs['bottom_x']:12.5f} {ours['bottom_x']:10.5f}")
    print("largest difference over the frames:",
          ", ".join(f"{k} {v:.2e}" for k, v in worst.items()))
    # The first contacts: each square's centre leaves free fall (fell less
    # than backward Euler's g t (t + dt) / 2 by more than 1e-4), the plate
    # comes within d_hat of the top square, the bottom square within d_hat
    # of the ground.
    for step in sorted(rows):
        r, t = rows[step], step * DT
        if float(r['plate_y']) - float(r['top_max_y']) < D_HAT:
            first.setdefault('tutorial plate', t)
        if float(r['bottom_min_y']) < D_HAT:
            first.setdefault('tutorial ground', t)
        free = 0.5 * 9.81 * t * t * (1 + DT / t)  # backward Euler falls g t (t + dt) / 2
        if float(r['bottom_y']) > 0.505 - free + 1e-4:
            first.setdefault('tutorial bottom leaves free fall', t)
        if float(r['top_y']) > 1.0 - free + 1e-4:
            first.setdefault('tutorial top leaves free fall', t)
    for frame in sorted(frames):
        t = frame * steps_per * DT
        points = frames[frame]
        if frame == 0:
            continue
        free = 0.5 * 9.81 * t * t * (1 + DT / t)
        if centre(points[PER_SQUARE:2 * PER_SQUARE])[1] > 0.505 - free + 1e-4:
            first.setdefault('elasto bottom leaves free fall', t)
        if centre(points[:PER_SQUARE])[1] > 1.0 - free + 1e-4:
            first.setdefault('elasto top leaves free fall', t)
    for k in sorted(first):
        print(f"{k}: t = {first[k]:.2f} s")


main()
