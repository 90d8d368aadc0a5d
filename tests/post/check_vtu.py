#!/usr/bin/python3
"""Independent reader of post's output: opens OUTDIR/CASE.pvd and every
vtu/frame_NNNN.vtu with meshio, and checks them against results.h5 and
model.h5 read with h5py. Run with Debian's /usr/bin/python3.

usage: check_vtu.py OUTDIR CASE_NAME     exit 0 if every check passes
"""
import os
import sys
import xml.etree.ElementTree as ElementTree

import h5py
import meshio
import numpy

FIELDS = {  # name: columns, as DESIGN.md names them
    "displacement": 3,
    "velocity": 3,
    "damage": 1,
    "equivalent_stress": 1,
    "equivalent_plastic_strain": 1,
    "stress": 6,
}

failures = []


def check(condition, message):
    if not condition:
        failures.append(message)


def main(outdir, case_name):
    model = h5py.File(os.path.join(outdir, "model.h5"), "r")
    results = h5py.File(os.path.join(outdir, "results.h5"), "r")
    reference = model["particles/position"][...]
    tetrahedra = model["mesh/tetrahedra"][...]
    count = int(results.attrs["frame_count"])

    pvd = ElementTree.parse(os.path.join(outdir, case_name + ".pvd"))
    root = pvd.getroot()
    check(root.tag == "VTKFile" and root.get("type") == "Collection",
          "the .pvd is not a VTK collection")
    datasets = root.findall("./Collection/DataSet")
    check(len(datasets) == count,
          "the .pvd lists %d frames, results.h5 holds %d"
          % (len(datasets), count))

    for k, entry in enumerate(datasets[:count]):
        group = results["frames/%06d" % k]
        # The time is printed with 17 digits: it reads back exactly.
        check(float(entry.get("timestep")) == float(group.attrs["time"]),
              "frame %d: timestep %s, results.h5 time %r"
              % (k, entry.get("timestep"), group.attrs["time"]))
        name = entry.get("file")
        check(name == "vtu/frame_%04d.vtu" % k, "frame %d file %s" % (k, name))
        path = os.path.join(outdir, name)
        with open(path, "rb") as raw:
            head = raw.read(2000)
        check(b'compressor="vtkZLibDataCompressor"' in head,
              "%s is not zlib compressed" % name)
        check(b'format="appended"' in head, "%s is not appended data" % name)
        with open(path, "rb") as raw:
            check(b'<AppendedData encoding="raw">' in raw.read(),
                  "%s: appended data is not raw binary" % name)

        mesh = meshio.read(path)
        u = group["displacement"][...]
        check(mesh.points.shape == reference.shape,
              "%s: %s points, model.h5 has %s"
              % (name, mesh.points.shape, reference.shape))
        # Both sides compute X + u in IEEE double: exactly equal.
        check(numpy.array_equal(mesh.points, reference + u),
              "%s: points are not X + u (max error %g)"
              % (name, numpy.abs(mesh.points - reference - u).max()))
        tetra = [block for block in mesh.cells if block.type == "tetra"]
        check(len(mesh.cells) == 1 and len(tetra) == 1,
              "%s: cells other than one block of tetrahedra" % name)
        if tetra:
            check(numpy.array_equal(tetra[0].data, tetrahedra),
                  "%s: the tetrahedra differ from model.h5" % name)
        check(set(FIELDS) <= set(mesh.point_data),
              "%s: point arrays %s lack some of %s"
              % (name, sorted(mesh.point_data), sorted(FIELDS)))
        for field, columns in FIELDS.items():
            if field not in mesh.point_data:
                continue
            values = numpy.asarray(mesh.point_data[field])
            expected = group[field][...]
            check(values.reshape(len(reference), -1).shape[1] == columns,
                  "%s: %s has shape %s" % (name, field, values.shape))
            # Stored as float64 on both sides: bit for bit.
            check(numpy.array_equal(values.reshape(expected.shape), expected),
                  "%s: %s differs from results.h5" % (name, field))

    for message in failures:
        print("FAIL:", message)
    print("check_vtu: %d frames, %d failures" % (count, len(failures)))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2]))
