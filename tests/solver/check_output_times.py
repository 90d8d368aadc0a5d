"""Checks where frames land (test_output_times.sh), from the files alone:
results.h5 read with h5py, the .pvd with an XML parser, history.csv.
A frame time T (an entry of output.times or a multiple of output.every
before the end) is written at the step nearest it, the first step n with
n dt >= T - dt/2, once per step; the frame at t = 0 and the one at the last
step are always written (docs/economy.md, "Outputs"). The step dt is taken
from the last frame (its time over its step), the expected steps are
computed here from END, EVERY and the times, and compared with the frames'
steps, times, the .pvd and the history rows.
usage: /usr/bin/python3 check_output_times.py OUTDIR NAME END EVERY T1 [T2...]
       (EVERY 0: no regular frames)"""
import csv
import math
import sys
import xml.etree.ElementTree as ET

import h5py

from checking import check, finish

outdir, name = sys.argv[1], sys.argv[2]
end, every = float(sys.argv[3]), float(sys.argv[4])
times = [float(t) for t in sys.argv[5:]]


with h5py.File(f"{outdir}/results.h5", "r") as results:
    count = int(results.attrs["frame_count"])
    frames = [results["frames"][f"{k:06d}"] for k in range(count)]
    steps = [int(f.attrs["step"]) for f in frames]
    stamps = [float(f.attrs["time"]) for f in frames]
dt = stamps[-1] / steps[-1]
last = math.ceil(end / dt - 1e-9)
wanted = list(times)
if every > 0:
    wanted += [k * every for k in range(1, int(end / every) + 2)]
expected = {0, last}
for t in wanted:
    if t < end - 0.5 * dt:
        expected.add(math.ceil(t / dt - 0.5))
expected = sorted(expected)
check(steps[-1] == last, f"last frame at step {steps[-1]} = {last} (dt {dt:.6g} s)")
check(steps == expected, f"frame steps {steps}, expected {expected}")
check(count == len(expected), f"{count} frames, expected {len(expected)}")
check(all(abs(s - n * dt) <= 1e-12 * end for s, n in zip(stamps, steps)),
      "every frame records the time of its step")
for t in times:
    if t < end - 0.5 * dt:
        nearest = min(stamps, key=lambda s: abs(s - t))
        check(abs(nearest - t) <= 0.5 * dt * (1 + 1e-9),
              f"a frame at {nearest:.6g} s, within half a step of {t} s")

pvd = ET.parse(f"{outdir}/{name}.pvd").getroot()
pvd_times = [float(d.get("timestep")) for d in pvd.iter("DataSet")]
check(pvd_times == stamps, f".pvd lists the {len(pvd_times)} frame times")
with open(f"{outdir}/history.csv") as history:
    rows = list(csv.DictReader(history))
check([int(r["step"]) for r in rows] == steps,
      f"history.csv has a row at every frame's step ({len(rows)} rows)")
finish()
