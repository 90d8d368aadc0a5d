"""Checks a half model's outputs (test_economy_cli.sh), read with h5py and
meshio, independent readers of geoscni's files:
- results.h5 frames hold exactly the fields of output.fields;
- the symmetry plane x = PLANE holds: u_x = 0 to round-off at every
  particle on it, in every frame, while u_x elsewhere is not small (the
  Poisson expansion pushes on the plane, so the test can fail);
- the mirrored .vtu of the last frame has the half model's particles and
  the images of those off the plane, at reflected positions, with u_x and
  the stresses xy and xz of the images of opposite sign, and only the
  arrays of output.fields.
usage: /usr/bin/python3 check_economy.py OUTDIR PLANE FIELD [FIELD...]"""
import sys

import h5py
import meshio
import numpy as np

from checking import check, finish

outdir, plane, fields = sys.argv[1], float(sys.argv[2]), sys.argv[3:]


with h5py.File(f"{outdir}/model.h5", "r") as model:
    X = model["particles/position"][()]
n = len(X)
size = np.ptp(X, axis=0).max()
on = np.abs(X[:, 0] - plane) <= 1e-9 * size
check(on.sum() > 0, f"{on.sum()} of {n} particles on the plane x = {plane}")
with h5py.File(f"{outdir}/results.h5", "r") as results:
    frames = sorted(results["frames"].keys())
    worst_plane, largest_x, largest = 0.0, 0.0, 0.0
    for name in frames:
        group = results["frames"][name]
        check(sorted(group.keys()) == sorted(fields),
              f"frame {name} holds {sorted(group.keys())}")
        u = group["displacement"][()]
        worst_plane = max(worst_plane, np.abs(u[on, 0]).max())
        largest_x = max(largest_x, np.abs(u[:, 0]).max())
        largest = max(largest, np.abs(u).max())
    last = results["frames"][frames[-1]]
    u = last["displacement"][()]
    stress = last["stress"][()]
# exact constraint: round-off of the boundary correction, 1e-12 of |u|
check(worst_plane <= 1e-12 * largest,
      f"|u_x| on the plane {worst_plane:.2e} m (largest |u| {largest:.2e} m)")
check(largest_x > 1e-2 * largest,
      f"largest |u_x| {largest_x:.2e} m: the plane carries load")

mesh = meshio.read(f"{outdir}/vtu/frame_{len(frames) - 1:04d}.vtu")
image = np.where(on, np.arange(n), n + np.cumsum(~on) - 1)
check(len(mesh.points) == n + (~on).sum(),
      f"{len(mesh.points)} mirrored points = {n} + {(~on).sum()} images")
check(sorted(mesh.point_data.keys()) == sorted(fields),
      f"vtu arrays {sorted(mesh.point_data.keys())}")
x = X + u
reflected = x.copy()
reflected[:, 0] = 2 * plane - x[:, 0]
# positions and fields are copied or negated: exact but for float printing
check(np.allclose(mesh.points[:n], x, rtol=0, atol=1e-12 * size),
      "the half model's points at X + u")
check(np.allclose(mesh.points[image], reflected, rtol=0, atol=1e-12 * size),
      "the images at the reflected positions")
mu = mesh.point_data["displacement"]
check(np.array_equal(mu[image[~on]], u[~on] * [-1, 1, 1]),
      "image displacement (-u_x, u_y, u_z)")
ms = mesh.point_data["stress"]
check(np.array_equal(ms[image[~on]], stress[~on] * [1, 1, 1, -1, 1, -1]),
      "image stress (xx, yy, zz, -xy, yz, -xz)")
check(np.abs(stress[:, 3]).max() > 0, "the stress xy is not zero everywhere")
finish()
