#!/usr/bin/python3
"""Seeded mutation fuzzing of geoscni's inputs (issue 19, point 2).

Four targets, each mutated deterministically from --seed (the same seed and
count give the same inputs on every machine):
  case     the case file: lines deleted, doubled or swapped, numbers replaced
           by 0, negatives, 1e308, nan, words; keys misspelt; indentation,
           colons and brackets broken; bytes flipped (also to non-UTF-8);
           the file cut short. Run with `geoscni check`.
  geo      the gmsh geometry: the same on box.geo. Run with `geoscni check`.
  model    model.h5 of a valid pre: bytes flipped or the file cut short.
           Run with `geoscni solve`.
  results  results.h5 of a valid solve: the same. Run with `geoscni post`.
Every outcome must be exit 0, or exit 2 with a message naming the file that
was mutated (or the case file that leads to it); never another status, a
signal, a hang (--timeout), or a partial output: no `*.part` or temporary
file left and, when a stage refuses, no final-named output of its own
(solve: results.h5 and history.csv; post: the .pvd). A damaged results.h5
that post accepts (the change in bytes it does not read) must give the
.vtu files of the undamaged one, byte for byte.

Usage: fuzz.py GEOSCNI [--seed S] [--count N] [--targets case,geo,model,results]
                       [--timeout SECONDS] [--keep DIR]
Prints one line per target and every failure with the mutated input kept
under DIR (default a temporary folder, removed when all pass)."""
import argparse
import os
import random
import re
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))

CASE = """geometry: box.geo
particles:
  spacing: 0.5
integration: {method: scni, stabilization: nsni, coefficient: 0.1}
material:
  density: 1880
  bulk_modulus: 27.4e6
  shear_modulus: 9.15e6
  damage: {e0: 0.02, ef: 5.0}
  drucker_prager: {alpha: 0.07, R: 0.19e6}
gravity: [0, 0, -9.81]
boundary:
  bottom: {fix: [x, y, z]}
  top: {velocity: [null, null, -0.01]}
time:
  end: 0.3
  step: auto
  ramp: 0.1
damping: {local: 0.1}
output:
  every: 0.1
"""

NUMBERS = ["0", "-1", "1e308", "-1e308", "1e-320", "nan", ".inf", "-0",
           "abc", "''", "[1, 2]", "{}", "99999999999999999999", "0x10", "~"]
WORDS = ["spacing", "material", "boundary", "time", "end", "fix", "velocity",
         "geometry", "density", "x", "null", "true"]


def mutate_text(text, rng):
    """One to three mutations of a text file, as bytes."""
    lines = text.split("\n")
    for _ in range(rng.randint(1, 3)):
        op = rng.randrange(10)
        k = rng.randrange(len(lines)) if lines else 0
        if op == 0 and lines:
            del lines[k]
        elif op == 1 and lines:
            lines.insert(k, lines[k])
        elif op == 2 and len(lines) > 1:
            j = rng.randrange(len(lines))
            lines[k], lines[j] = lines[j], lines[k]
        elif op == 3 and lines:  # a number replaced
            numbers = list(re.finditer(r"-?\d+(\.\d*)?(e[-+]?\d+)?", lines[k]))
            if numbers:
                m = rng.choice(numbers)
                lines[k] = (lines[k][:m.start()] + rng.choice(NUMBERS) +
                            lines[k][m.end():])
        elif op == 4 and lines:  # a key or word misspelt or swapped
            words = list(re.finditer(r"[A-Za-z_]+", lines[k]))
            if words:
                m = rng.choice(words)
                new = (rng.choice(WORDS) if rng.random() < 0.5 else
                       m.group()[::-1])
                lines[k] = lines[k][:m.start()] + new + lines[k][m.end():]
        elif op == 5 and lines:  # indentation
            lines[k] = (" " * rng.randint(0, 5)) + lines[k].lstrip()
        elif op == 6 and lines:  # punctuation broken
            for a, b in ((":", " "), ("[", ""), ("]", ""), ("{", ""),
                         ("}", ""), (",", ""), ("\"", "'")):
                if a in lines[k] and rng.random() < 0.5:
                    lines[k] = lines[k].replace(a, b, 1)
                    break
        elif op == 7 and lines:  # random printable characters
            pos = rng.randint(0, len(lines[k]))
            junk = "".join(chr(rng.randint(32, 126))
                           for _ in range(rng.randint(1, 6)))
            lines[k] = lines[k][:pos] + junk + lines[k][pos:]
        elif op == 8:  # a line of its own
            lines.insert(k, rng.choice(["---", "...", "&a", "*a", "%YAML 9",
                                        "- x", "? y", "!!binary ab", "\t",
                                        "<<: *a", "key: |", "x: >"]))
    data = "\n".join(lines).encode("utf-8", "replace")
    if rng.random() < 0.3 and data:  # bytes flipped, also to non-UTF-8
        data = bytearray(data)
        for _ in range(rng.randint(1, 4)):
            data[rng.randrange(len(data))] = rng.randrange(256)
        data = bytes(data)
    if rng.random() < 0.15 and data:  # cut short
        data = data[:rng.randrange(len(data))]
    return data


def mutate_binary(data, rng):
    data = bytearray(data)
    if rng.random() < 0.2:
        return bytes(data[:rng.randrange(len(data))])  # cut short
    for _ in range(rng.choice([1, 1, 1, 2, 4, 16])):
        at = rng.randrange(len(data))
        data[at] ^= 1 << rng.randrange(8) if rng.random() < 0.7 else \
            rng.randrange(1, 256)
    return bytes(data)


def run(command, timeout, cwd=None):
    try:
        p = subprocess.run(command, cwd=cwd, capture_output=True,
                           timeout=timeout, text=True, errors="replace")
        return p.returncode, p.stdout + p.stderr
    except subprocess.TimeoutExpired:
        return "hang", ""


def leftovers(folder):
    """Temporary or partial files left under folder."""
    found = []
    for base, _, files in os.walk(folder):
        for name in files:
            if name.endswith(".part") or ".tmp" in name or name.startswith(".tmp"):
                found.append(os.path.join(base, name))
    return found


class Fuzz:
    def __init__(self, geoscni, work, timeout):
        self.geoscni, self.work, self.timeout = geoscni, work, timeout
        self.failures = []
        base = os.path.join(work, "base")
        os.makedirs(base)
        shutil.copy(os.path.join(ROOT, "geometries", "box.geo"), base)
        with open(os.path.join(base, "case.yaml"), "w") as f:
            f.write(CASE)
        status, out = run([geoscni, "run", "case.yaml", "-o", "out", "-q",
                           "--no-pictures"], 600, cwd=base)
        if status != 0:
            sys.exit(f"fuzz: the valid case does not run ({status}):\n{out}")
        self.base = base

    def judge(self, target, index, status, out, named, forbidden, folder):
        problem = None
        if status == "hang":
            problem = f"no answer within {self.timeout} s"
        elif status not in (0, 2):
            problem = f"exit status {status}"
        elif status == 2 and not any(n in out for n in named):
            problem = "the message names none of " + ", ".join(named)
        elif status == 2 and [f for f in forbidden if os.path.exists(f)]:
            problem = "a refused stage left " + ", ".join(
                f for f in forbidden if os.path.exists(f))
        elif leftovers(folder):
            problem = "partial files left: " + ", ".join(leftovers(folder))
        if problem:
            self.failures.append(f"{target} #{index}: {problem} (kept in "
                                 f"{folder})\n  {out.strip()[-400:]}")
        return problem is None

    def case(self, index, rng):
        folder = os.path.join(self.work, f"case_{index}")
        os.makedirs(folder)
        shutil.copy(os.path.join(self.base, "box.geo"), folder)
        path = os.path.join(folder, "case.yaml")
        with open(path, "wb") as f:
            f.write(mutate_text(CASE, rng))
        status, out = run([self.geoscni, "check", path], self.timeout)
        return status, self.judge("case", index, status, out,
                                  [path, "case.yaml"], [], folder)

    def geo(self, index, rng):
        folder = os.path.join(self.work, f"geo_{index}")
        os.makedirs(folder)
        with open(os.path.join(self.base, "box.geo")) as f:
            text = f.read()
        geo = os.path.join(folder, "box.geo")
        with open(geo, "wb") as f:
            f.write(mutate_text(text, rng))
        path = os.path.join(folder, "case.yaml")
        with open(path, "w") as f:
            f.write(CASE)
        status, out = run([self.geoscni, "check", path], self.timeout)
        return status, self.judge("geo", index, status, out,
                                  [geo, path, "box.geo"], [], folder)

    def model(self, index, rng):
        folder = os.path.join(self.work, f"model_{index}")
        out_dir = os.path.join(folder, "out")
        os.makedirs(out_dir)
        for name in ("box.geo", "case.yaml"):
            shutil.copy(os.path.join(self.base, name), folder)
        with open(os.path.join(self.base, "out", "model.h5"), "rb") as f:
            data = f.read()
        model = os.path.join(out_dir, "model.h5")
        with open(model, "wb") as f:
            f.write(mutate_binary(data, rng))
        status, out = run([self.geoscni, "solve", os.path.join(folder, "case.yaml"),
                           "-o", out_dir, "-q"], self.timeout)
        return status, self.judge(
            "model", index, status, out, [model],
            [os.path.join(out_dir, n) for n in ("results.h5", "history.csv")],
            folder)

    def results(self, index, rng):
        folder = os.path.join(self.work, f"results_{index}")
        shutil.copytree(os.path.join(self.base, "out"), folder)
        for name in os.listdir(folder):  # what post makes, made again
            if name not in ("model.h5", "results.h5", "history.csv"):
                path = os.path.join(folder, name)
                shutil.rmtree(path) if os.path.isdir(path) else os.remove(path)
        results = os.path.join(folder, "results.h5")
        with open(results, "rb") as f:
            data = f.read()
        with open(results, "wb") as f:
            f.write(mutate_binary(data, rng))
        status, out = run([self.geoscni, "post", folder, "-q", "--no-pictures"],
                          self.timeout)
        pvd = [os.path.join(folder, n) for n in os.listdir(folder)
               if n.endswith(".pvd")]
        ok = self.judge("results", index, status, out, [results], pvd, folder)
        if ok and status == 0:  # what post wrote is what it wrote before
            made = os.path.join(folder, "vtu")
            base = os.path.join(self.base, "out", "vtu")
            names = sorted(os.listdir(base))
            differ = [n for n in names if not os.path.exists(
                os.path.join(made, n)) or open(os.path.join(made, n), "rb").read()
                != open(os.path.join(base, n), "rb").read()]
            if differ or sorted(os.listdir(made)) != names:
                ok = False
                self.failures.append(
                    f"results #{index}: exit 0 but vtu/ differs from the "
                    f"undamaged file's ({', '.join(differ) or 'the names'}; "
                    f"kept in {folder})")
        return status, ok


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("geoscni")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--count", type=int, default=10)
    parser.add_argument("--targets", default="case,geo,model,results")
    parser.add_argument("--timeout", type=float, default=120)
    parser.add_argument("--keep")
    args = parser.parse_args()
    work = args.keep or tempfile.mkdtemp(prefix="geoscni-fuzz-")
    os.makedirs(work, exist_ok=True)
    fuzz = Fuzz(os.path.abspath(args.geoscni), work, args.timeout)
    for target in args.targets.split(","):
        counts = {}
        for i in range(args.count):
            rng = random.Random(f"{args.seed}:{target}:{i}")
            status, ok = getattr(fuzz, target)(i, rng)
            key = str(status) if ok else "FAIL"
            counts[key] = counts.get(key, 0) + 1
            if ok and not args.keep:
                shutil.rmtree(os.path.join(work, f"{target}_{i}"))
        print(f"{target}: {args.count} mutations, seed {args.seed}: " +
              ", ".join(f"exit {k}: {v}" if k != "FAIL" else f"FAILED: {v}"
                        for k, v in sorted(counts.items())), flush=True)
    for failure in fuzz.failures:
        print("FAIL " + failure)
    print(f"fuzz: {len(fuzz.failures)} failures")
    if not fuzz.failures and not args.keep:
        shutil.rmtree(work)
    return 1 if fuzz.failures else 0


if __name__ == "__main__":
    sys.exit(main())
