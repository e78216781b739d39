#!/usr/bin/python3
"""Mutation harness for issue 12 item 5 ("every input finishes or is refused within seconds").

Makes random mutations of scene files with a fixed seed (extreme numbers, changed value types,
deleted, duplicated and swapped keys), runs the release tools on each, `slice-joints` and then,
if that succeeded, `slice-cut`, each under a timeout, and lists the inputs that are slow (a stage
over --slow seconds), time out, crash, or exit with 2 (an internal error). Exit 1 with a message
is the right answer to bad input and is not listed.

    /usr/bin/python3 tests/fuzz/mutate_scenes.py [--count 5000] [--seed 12] [--jobs 2]
        [--tools build/tools] [--timeout 10] [--slow 2] [--save DIR] [scene.toml ...]

Default scenes: data/cube-3sets.toml and data/table3-persistent.toml (the issue's two).
--save DIR writes every listed input there as <n>-<what>.toml with the mutation in a comment at
the top (tests/fuzz/regressions/slow/ holds the ones found so far). The exit code is 0 if
nothing was listed, 1 otherwise. Times are wall times of the release build on a shared 2-core
machine: compare them with --slow, not with each other.
"""
import argparse
import concurrent.futures
import os
import random
import re
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))

# Numbers a careless script or a unit slip produces, and the edges of double and int64.
EXTREME = [
    "0", "-0.0", "-1", "1e-300", "5e-324", "2.2250738585072014e-308", "1e-12", "1e-9", "1e-6",
    "1e-4", "1e6", "1e9", "1e12", "1e15", "1e18", "1e300", "1.7976931348623157e308", "-1e308",
    "9223372036854775807", "-9223372036854775808", "4294967296", "inf", "-inf", "nan", "89.9999999",
    "90.000000001", "359.9999999999", "360", "-360", "0.1", "3", "1000000",
]
# Values of another TOML type.
OTHER_TYPES = [
    '"1"', '""', "true", "false", "[]", "[1, 2]", "[[1, 2, 3]]", "{}", "{ a = 1 }",
    "1979-05-27T07:32:00Z", "1979-05-27", "07:32:00", '"' + "x" * 200 + '"', "[1, 2, 3, 4]",
]
KEYS = [
    "tolerance", "seed", "max_joints", "order", "min_inscribed_diameter", "max_aspect_ratio",
    "dip", "dip_direction", "spacing", "offset", "kind", "keep", "friction_angle", "cohesion",
    "fisher_kappa", "density", "count", "p32", "p10", "size", "shape", "aspect", "sides",
    "rotation",
]
NUMBER = re.compile(r"(?<![\w.])[-+]?(?:\d+\.?\d*(?:[eE][-+]?\d+)?|inf|nan)(?![\w.])")
KEY_LINE = re.compile(r"^(\s*)([A-Za-z_][A-Za-z0-9_]*)(\s*=\s*)(.*?)(\s*(?:#.*)?)$")


def strip_comments(text):
    """The scene without comment-only lines and trailing comments, so mutations hit values."""
    out = []
    for line in text.splitlines():
        if line.lstrip().startswith("#") or not line.strip():
            continue
        m = KEY_LINE.match(line)
        out.append(m.group(1) + m.group(2) + m.group(3) + m.group(4) if m else line)
    return out


def mutate(lines, rng):
    """One to three random edits; returns (new lines, description)."""
    lines = list(lines)
    what = []
    for _ in range(rng.choice([1, 1, 1, 2, 3])):
        kind = rng.choice(["number", "number", "number", "scale", "type", "type", "delete",
                           "duplicate", "swap", "insert"])
        keyed = [i for i, l in enumerate(lines) if KEY_LINE.match(l)]
        numbered = [i for i, l in enumerate(lines) if NUMBER.search(l) and KEY_LINE.match(l)]
        if kind in ("number", "scale") and numbered:
            i = rng.choice(numbered)
            m = KEY_LINE.match(lines[i])
            spans = [s.span() for s in NUMBER.finditer(m.group(4))]
            a, b = rng.choice(spans)
            value = m.group(4)
            old = value[a:b]
            if kind == "number":
                new = rng.choice(EXTREME)
            else:
                try:
                    new = repr(float(old) * 10.0 ** rng.randint(-12, 12))
                except ValueError:
                    new = rng.choice(EXTREME)
            lines[i] = m.group(1) + m.group(2) + m.group(3) + value[:a] + new + value[b:]
            what.append(f"{m.group(2)}: {old} -> {new}")
        elif kind == "type" and keyed:
            i = rng.choice(keyed)
            m = KEY_LINE.match(lines[i])
            new = rng.choice(OTHER_TYPES)
            lines[i] = m.group(1) + m.group(2) + m.group(3) + new
            what.append(f"{m.group(2)} = {new[:20]}")
        elif kind == "delete" and keyed:
            i = rng.choice(keyed)
            what.append(f"delete {KEY_LINE.match(lines[i]).group(2)}")
            del lines[i]
        elif kind == "duplicate":
            starts = [i for i, l in enumerate(lines) if l.startswith("[[")]
            if starts:
                i = rng.choice(starts)
                j = next((k for k in range(i + 1, len(lines)) if lines[k].startswith("[")),
                         len(lines))
                block = lines[i:j]
                copies = rng.choice([1, 1, 2, 10])
                lines.extend(block * copies)
                what.append(f"{copies} more copies of {lines[i]} at line {i + 1}")
        elif kind == "swap" and len(keyed) > 1:
            i, j = rng.sample(keyed, 2)
            mi, mj = KEY_LINE.match(lines[i]), KEY_LINE.match(lines[j])
            lines[i] = mi.group(1) + mi.group(2) + mi.group(3) + mj.group(4)
            lines[j] = mj.group(1) + mj.group(2) + mj.group(3) + mi.group(4)
            what.append(f"swap values of {mi.group(2)} and {mj.group(2)}")
        elif kind == "insert":
            tables = [i for i, l in enumerate(lines) if l.startswith("[")]
            if tables:
                i = rng.choice(tables)
                key = rng.choice(KEYS)
                value = rng.choice(EXTREME + OTHER_TYPES[:4])
                lines.insert(i + 1, f"{key} = {value}")
                what.append(f"insert {key} = {value} under {lines[i]}")
    return lines, "; ".join(what) or "unchanged"


def run(cmd, timeout):
    """(exit code or 'timeout' or 'signal N', seconds, last stderr line)."""
    start = time.monotonic()
    try:
        p = subprocess.run(cmd, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                           stderr=subprocess.PIPE, timeout=timeout)
        code = p.returncode if p.returncode >= 0 else f"signal {-p.returncode}"
        err = p.stderr.decode(errors="replace").strip().splitlines()
        return code, time.monotonic() - start, err[-1] if err else ""
    except subprocess.TimeoutExpired:
        return "timeout", time.monotonic() - start, ""


def check(args, n, text, what):
    """Runs one mutated scene; returns a result dict."""
    with tempfile.TemporaryDirectory(prefix="rockslice-mutate-") as tmp:
        scene = os.path.join(tmp, "scene.toml")
        with open(scene, "w") as f:
            f.write(text)
        tools = args.tools
        r = {"n": n, "what": what, "text": text, "stages": []}
        code, secs, err = run([os.path.join(tools, "slice-joints"), "-q", scene, "-o",
                               os.path.join(tmp, "joints.h5")], args.timeout)
        r["stages"].append(("slice-joints", code, secs, err))
        if code == 0:
            code, secs, err = run([os.path.join(tools, "slice-cut"), "-q",
                                   os.path.join(tmp, "joints.h5"), "-o",
                                   os.path.join(tmp, "blocks.h5")], args.timeout)
            r["stages"].append(("slice-cut", code, secs, err))
        return r


def listed(r, slow):
    return any(code not in (0, 1) or secs > slow for _, code, secs, _ in r["stages"])


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("scenes", nargs="*", default=[
        os.path.join(ROOT, "data", "cube-3sets.toml"),
        os.path.join(ROOT, "data", "table3-persistent.toml")])
    ap.add_argument("--count", type=int, default=5000)
    ap.add_argument("--seed", type=int, default=12)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--tools", default=os.path.join(ROOT, "build", "tools"))
    ap.add_argument("--timeout", type=float, default=10.0)
    ap.add_argument("--slow", type=float, default=2.0)
    ap.add_argument("--save", help="write the listed inputs into this folder")
    args = ap.parse_args()

    rng = random.Random(args.seed)
    bases = [strip_comments(open(s).read()) for s in args.scenes]
    names = [os.path.basename(s) for s in args.scenes]
    jobs = []
    for n in range(args.count):
        b = n % len(bases)
        lines, what = mutate(bases[b], rng)
        jobs.append((n, "\n".join(lines) + "\n", f"{names[b]}: {what}"))

    found = []
    codes = {}
    start = time.monotonic()
    with concurrent.futures.ThreadPoolExecutor(args.jobs) as pool:
        for r in pool.map(lambda j: check(args, *j), jobs):
            last = r["stages"][-1]
            codes[(last[0], last[1])] = codes.get((last[0], last[1]), 0) + 1
            if listed(r, args.slow):
                found.append(r)
                stages = ", ".join(f"{s} {c} {t:.1f} s" for s, c, t, _ in r["stages"])
                print(f"#{r['n']}: {r['what']}\n    {stages}", flush=True)
    print(f"{args.count} mutations in {time.monotonic() - start:.0f} s; last stage and exit: " +
          ", ".join(f"{s} {c}: {k}" for (s, c), k in sorted(codes.items(), key=str)))
    print(f"{len(found)} listed (a stage over {args.slow} s, a timeout after {args.timeout} s, "
          "a signal or exit 2)")
    if args.save and found:
        os.makedirs(args.save, exist_ok=True)
        for r in found:
            stage, code, secs, _ = max(r["stages"], key=lambda s: s[2])
            tag = re.sub(r"[^a-z0-9]+", "-", f"{stage} {code}".lower()).strip("-")
            with open(os.path.join(args.save, f"{r['n']:04d}-{tag}.toml"), "w") as f:
                f.write(f"# mutate_scenes.py --seed {args.seed} #{r['n']}: {r['what']}\n")
                for s, c, t, _ in r["stages"]:
                    f.write(f"# {s}: {c} after {t:.1f} s (release build)\n")
                f.write(r["text"])
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
