"""A seeded mutation fuzzer for every reader Tailor has, and for its Python API.

Each case is a function of (seed, index) alone: a corpus file made from the repository's real
files (patterns, garment files, the character, the body mesh), mutated one to four times
(bit flips, bytes, truncation, deleted, duplicated or swapped lines, numbers replaced by extreme
values), then read through the public API as a user would (`tailor.read_pattern`,
`Garment.from_pattern`, `Garment.load` and its meshes, `read_mesh`, `AnimatedMesh`,
`read_pc2`), or a call of the API with hostile numbers and arrays.

A case passes when it returns or raises a `tailor.TailorError`. It fails when it raises
anything else (a pyo3 `PanicException` included: a `BaseException`), when the interpreter dies
(an abort in the allocator, a segfault) or when it runs over the hang limit. Cases run in a
worker process that notes each case's index before it runs, so a dead or stuck worker names
the case that killed it; the parent saves that case under `tests/fuzz/crashes/` (kept for good:
`tests/test_fuzz.py` replays every one) and starts a new worker after it.

    python tests/fuzz/fuzz.py --seed 1 --cases 2000            # what `make fuzz` runs, longer
    python tests/fuzz/fuzz.py --replay tests/fuzz/crashes/NAME  # one saved case
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import random
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
CRASHES = Path(__file__).resolve().parent / "crashes"
#: A case that uses more CPU time than this is a hang (seconds). CPU time, not wall time, so
#: that a loaded machine (another build, another engineer's tests) does not make hangs of
#: slow cases; a case blocked without using the CPU (a FIFO) is caught by BLOCKED_S of wall time.
HANG_S = 10.0
BLOCKED_S = 60.0
#: The worker's address-space cap: an input that asks for more is an allocation failure, which
#: Rust turns into an abort, which the parent records as a crash (and the machine survives).
MEMORY_CAP = 6 << 30

PATTERNS = REPO / "native/tailor-core/tests/data"
SAMPLES = REPO / "sample_blends"

# ----------------------------------------------------------------------------------- corpus


def _obj_subset(limit: int = 300) -> bytes:
    """The first `limit` vertices of the sample body (mean_all.obj) and the faces among them."""
    lines = (SAMPLES / "sources/mean_all.obj").read_text().splitlines()
    verts = [line for line in lines if line.startswith("v ")][:limit]
    faces = []
    for line in lines:
        if line.startswith("f "):
            idx = [int(t.split("/")[0]) for t in line.split()[1:]]
            if all(0 < i <= limit for i in idx):
                faces.append(line)
    return ("\n".join(verts + faces) + "\n").encode()


def _ply_from(obj: bytes, binary: bool) -> bytes:
    import numpy as np

    v = [list(map(float, line.split()[1:4])) for line in obj.decode().splitlines() if line.startswith("v ")]
    f = [[int(t.split("/")[0]) - 1 for t in line.split()[1:]] for line in obj.decode().splitlines()
         if line.startswith("f ")]
    head = (f"ply\nformat {'binary_little_endian' if binary else 'ascii'} 1.0\nelement vertex {len(v)}\n"
            "property float x\nproperty float y\nproperty float z\n"
            f"element face {len(f)}\nproperty list uchar int vertex_indices\nend_header\n").encode()
    if not binary:
        body = "".join(f"{a} {b} {c}\n" for a, b, c in v) + "".join(f"{len(t)} {' '.join(map(str, t))}\n" for t in f)
        return head + body.encode()
    out = bytearray(head + np.asarray(v, "<f4").tobytes())
    for t in f:
        out += bytes([len(t)]) + np.asarray(t, "<i4").tobytes()
    return bytes(out)


def _pc2(obj: bytes) -> bytes:
    import numpy as np

    import tailor

    v = np.array([list(map(float, line.split()[1:4])) for line in obj.decode().splitlines()
                  if line.startswith("v ")], np.float32)
    with tempfile.TemporaryDirectory() as d:
        tailor.write_pc2(Path(d) / "c.pc2", np.stack([v, v + 0.01, v + 0.02]), 1.0, 1.0)
        return (Path(d) / "c.pc2").read_bytes()


def _gltf_pair(obj: bytes) -> dict[str, bytes]:
    """A .gltf with an external .bin (the body subset), the layout the URI rules are about."""
    import numpy as np

    text = obj.decode().splitlines()
    v = np.array([list(map(float, line.split()[1:4])) for line in text if line.startswith("v ")], "<f4")
    t = np.array([[int(x.split("/")[0]) - 1 for x in line.split()[1:4]] for line in text if line.startswith("f ")],
                 "<u4")
    blob = v.tobytes() + t.tobytes()
    doc = {
        "asset": {"version": "2.0"},
        "buffers": [{"uri": "body.bin", "byteLength": len(blob)}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": v.nbytes},
                        {"buffer": 0, "byteOffset": v.nbytes, "byteLength": t.nbytes}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": len(v), "type": "VEC3"},
                      {"bufferView": 1, "componentType": 5125, "count": t.size, "type": "SCALAR"}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "nodes": [{"mesh": 0, "rotation": [0.0, 0.0, 0.38268343, 0.9238795], "translation": [0, 1, 0]}],
        "scenes": [{"nodes": [0]}],
        "scene": 0,
    }
    return {"body.gltf": json.dumps(doc, indent=1).encode(), "body.bin": blob}


def corpus() -> list[tuple[str, dict[str, bytes]]]:
    """(target, {file name: bytes}) for every seed input; the first file is the one opened."""
    out: list[tuple[str, dict[str, bytes]]] = []
    for sub, target in (("dxf", "pattern"), ("svg", "pattern"), ("garmentcode", "pattern")):
        for p in sorted((PATTERNS / sub).iterdir()):
            if p.suffix.lower() in (".dxf", ".svg", ".json"):
                out.append((target, {p.name: p.read_bytes()}))
    for name in ("skirt", "tshirt", "trousers"):
        out.append(("garment", {f"{name}.json": (SAMPLES / f"{name}.json").read_bytes(),
                                f"{name}.bin": (SAMPLES / f"{name}.bin").read_bytes()}))
    obj = _obj_subset()
    out.append(("mesh", {"body.obj": obj}))
    out.append(("mesh", {"body.ply": _ply_from(obj, binary=False)}))
    out.append(("mesh", {"body_bin.ply": _ply_from(obj, binary=True)}))
    out.append(("mesh", _gltf_pair(obj)))
    out.append(("animated", {"character.glb": (SAMPLES / "character.glb").read_bytes()}))
    out.append(("pc2", {"body.pc2": _pc2(obj)}))
    return out


# -------------------------------------------------------------------------------- mutation

EXTREMES = [b"1e308", b"-1e308", b"NaN", b"nan", b"inf", b"-inf", b"0", b"-0", b"1e-300", b"4294967295",
            b"4294967296", b"-1", b"18446744073709551615", b"9e18", b"1e6", b"3", b"", b"1.8e19", b"-2147483649"]
TOKENS = [b"0\n", b"\n", b"EOF", b"SECTION", b"ENDSEC", b"{", b"}", b"[", b"]", b",", b'"', b"<", b"/>", b"..",
          b"../", b"/dev/zero", b"/etc/passwd", b"%2E%2E/", b"null", b"true", b"-", b"e", b"Z", b"M", b"C", b"A"]
NUMBER = re.compile(rb"-?\d+(?:\.\d+)?(?:[eE][-+]?\d+)?")


def mutate(rng: random.Random, data: bytes) -> bytes:
    """One to three mutations. Most replace a number by an extreme value or move whole lines,
    which keeps the file parseable so the case reaches the code behind the parser; the rest
    work on bytes (flips, truncation, deleted, repeated or inserted runs)."""
    b = bytearray(data)
    for _ in range(rng.randint(1, 3)):
        if not b:
            b += rng.choice(TOKENS)
            continue
        r = rng.random()
        i = rng.randrange(len(b))
        if r < 0.45:
            nums = [m for m in NUMBER.finditer(bytes(b), max(0, i - 4096), min(len(b), i + 4096))]
            if nums:
                m = rng.choice(nums)
                b[m.start():m.end()] = rng.choice(EXTREMES)
        elif r < 0.60:
            lines = bytes(b).split(b"\n")
            if len(lines) > 2:
                k, j = rng.randrange(len(lines)), rng.randrange(len(lines))
                choice = rng.randrange(3)
                if choice == 0:
                    del lines[k]
                elif choice == 1:
                    lines.insert(k, lines[j])
                else:
                    lines[k], lines[j] = lines[j], lines[k]
                b = bytearray(b"\n".join(lines))
        elif r < 0.70:
            b[i] ^= 1 << rng.randrange(8)
        elif r < 0.75:
            b[i] = rng.randrange(256)
        elif r < 0.80:
            del b[i:]
        elif r < 0.85:
            del b[i:min(len(b), i + rng.randint(1, 64))]
        elif r < 0.90:
            j = min(len(b), i + rng.randint(1, 256))
            b[i:i] = b[i:j] * rng.randint(1, 8)
        else:
            b[i:i] = rng.choice(TOKENS)
    return bytes(b)


def make_case(seed: int, index: int, seeds: list[tuple[str, dict[str, bytes]]]) -> tuple[str, dict[str, bytes]]:
    """Case `index` of run `seed`: a target and its files (deterministic)."""
    rng = random.Random(f"{seed}:{index}")
    if rng.random() < 0.08:
        return "api", {"call.json": json.dumps({"seed": rng.randrange(1 << 30)}).encode()}
    target, files = rng.choice(seeds)
    files = dict(files)
    names = list(files)
    # A garment's manifest most of the time, its sidecar sometimes; a glTF's buffer too.
    victim = names[0] if len(names) == 1 or rng.random() < 0.75 else rng.choice(names[1:])
    files[victim] = mutate(rng, files[victim])
    return target, files


# --------------------------------------------------------------------------------- targets

HOSTILE = [0.0, -0.0, -1.0, 1e-12, 1e-6, 1e30, -1e30, 3e38, float("nan"), float("inf"), float("-inf"), 0.5, 2.0]


def run_api(seed: int) -> None:
    """Hostile numbers and arrays through the calls that take them."""
    import numpy as np

    import tailor

    rng = random.Random(seed)
    h = lambda: rng.choice(HOSTILE)  # noqa: E731
    choice = rng.randrange(6)
    if choice == 0:
        tailor.sewn_tube(width=h(), height=h(), edge=max(h(), 0.0) if rng.random() < 0.3 else h(), gap=h())
        return
    if choice == 1:
        field = rng.choice(["substeps", "iterations", "tolerance", "air_damping", "ramp_closing_speed", "gravity"])
        value = rng.choice([h(), -1, 2**40, "x", [h(), h(), h()], None])
        tailor.Settings(**{field: value})
        return
    d = tailor.sewn_tube(edge=0.1)
    sim = tailor.Simulation(d["positions"], d["triangles"], d["rest"])
    n = sim.num_particles
    if choice == 2:
        rng.choice([
            lambda: sim.add_sphere_collider((h(), h(), h()), h()),
            lambda: sim.add_capsule_collider((h(), 0, 0), (0, h(), 0), h()),
            lambda: sim.add_plane_collider((0, h(), 0), (h(), h(), h())),
        ])()
        sim.step(1 / 30)
    elif choice == 3:
        values = rng.choice([np.full(n, rng.choice([2**31 - 1, -2**31, 2**32 + 1, 70000, 3])), np.zeros(n + 1),
                             np.full(n, h()), [[1, 2]], "abc"])
        rng.choice([sim.set_particle_levels, lambda v: sim.set_mass_scale(v)])(values)
    elif choice == 4:
        p = np.asarray(d["positions"]).copy()
        p[rng.randrange(n)] = [h(), h(), h()]
        sim.positions = rng.choice([p, p[:-1], p.T, p.astype(np.float64), p.tolist()])
        sim.step(rng.choice([1 / 30, h()]))
    else:
        sim.thickness = h()
        sim.set_self_collision(enabled=True, radius=abs(h()) if rng.random() < 0.5 else h())
        sim.step(1 / 30)


def run_target(target: str, folder: Path, names: list[str]) -> None:
    import tailor

    path = folder / names[0]
    selftest = os.environ.get("TAILOR_FUZZ_SELFTEST")
    if selftest:
        # tests/test_fuzz.py: a worker that dies, hangs or raises must be caught and named.
        index = int(selftest)
        if index == 3:
            os.abort()
        if index == 5:
            while True:  # spins: a hang by CPU time
                pass
        if index == 6:
            time.sleep(1e6)  # blocks: a hang by wall time
        if index == 7:
            raise ValueError("self-test: not a TailorError")
    if target == "api":
        run_api(json.loads(path.read_text())["seed"])
    elif target == "pattern":
        tailor.read_pattern(path)
        tailor.list_sizes(path)
        garment = tailor.Garment.from_pattern(path, edge=0.04)
        garment.meshes()
    elif target == "garment":
        garment = tailor.Garment.load(path)
        garment.meshes()
        for seam in garment.seams:
            seam.resolve(garment.meshes())
        garment.setup
        garment.attach_groups()
    elif target == "mesh":
        tailor.read_mesh(path)
    elif target == "animated":
        scene = tailor.AnimatedMesh(str(path))
        for k, (_, duration) in enumerate(scene.animations[:2]):
            for t in (0.0, duration * 0.37, duration + 1.0):
                scene.positions_at(t, k)
    elif target == "pc2":
        tailor.read_pc2(path)
    else:
        raise ValueError(f"unknown target {target}")


def classify(exc: BaseException | None) -> str:
    import tailor

    if exc is None:
        return "ok"
    if isinstance(exc, tailor.TailorError):
        return "error"
    return "exception"


# ---------------------------------------------------------------------------------- worker


def worker(seed: int, start: int, stop: int, progress: Path) -> None:
    """Runs cases start..stop-1, noting each index in `progress` before it runs and printing
    a JSON line per case that ends in a Python exception other than TailorError."""
    try:
        import resource

        resource.setrlimit(resource.RLIMIT_AS, (MEMORY_CAP, MEMORY_CAP))
    except (ImportError, ValueError, OSError):
        pass
    seeds = corpus()
    counts: dict[str, int] = {}
    with tempfile.TemporaryDirectory(prefix="tailor-fuzz-") as tmp:
        for k in range(start, stop):
            target, files = make_case(seed, k, seeds)
            progress.write_text(f"{k}\n")
            if "TAILOR_FUZZ_SELFTEST" in os.environ:
                os.environ["TAILOR_FUZZ_SELFTEST"] = str(k)
            outcome, detail = run_files(target, files, Path(tmp) / str(k))
            counts[f"{target} {outcome}"] = counts.get(f"{target} {outcome}", 0) + 1
            if outcome == "exception":
                print(json.dumps({"case": k, "target": target, "detail": detail}), flush=True)
            if (k - start) % 200 == 199:  # so that a worker killed later loses few counts
                print(json.dumps({"counts": counts}), flush=True)
                counts = {}
    print(json.dumps({"counts": counts}), flush=True)
    progress.write_text("done\n")


def run_files(target: str, files: dict[str, bytes], folder: Path) -> tuple[str, str]:
    folder.mkdir(parents=True, exist_ok=True)
    for name, data in files.items():
        (folder / name).write_bytes(data)
    exc = None
    try:
        run_target(target, folder, list(files))
    except BaseException as e:  # noqa: BLE001 - a PanicException is a BaseException
        if isinstance(e, KeyboardInterrupt):
            raise
        exc = e
    shutil.rmtree(folder, ignore_errors=True)
    return classify(exc), f"{type(exc).__name__}: {exc}"[:500] if exc else ""


# ---------------------------------------------------------------------------------- parent


def save_case(seed: int, index: int, kind: str, detail: str, seeds, out_dir: Path = CRASHES) -> Path:
    """Keeps a failing case as a regression input: its files and a case.json saying how to run it."""
    target, files = make_case(seed, index, seeds)
    digest = hashlib.sha1(b"".join(files[n] for n in sorted(files))).hexdigest()[:12]
    folder = out_dir / f"{target}-{kind}-{digest}"
    folder.mkdir(parents=True, exist_ok=True)
    for name, data in files.items():
        (folder / name).write_bytes(data)
    (folder / "case.json").write_text(json.dumps(
        {"target": target, "files": list(files), "kind": kind, "detail": detail, "seed": seed, "index": index},
        indent=1) + "\n")
    return folder


def cpu_seconds(pid: int) -> float:
    """User and system CPU time of process `pid` so far (Linux /proc; 0 elsewhere)."""
    try:
        fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
        return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")
    except (OSError, IndexError, ValueError):
        return 0.0


def fuzz(seed: int, cases: int, hang_s: float = HANG_S, out_dir: Path = CRASHES, log=print,
         blocked_s: float = BLOCKED_S) -> dict:
    """Runs `cases` cases of run `seed` in workers; returns counts and the failures found."""
    seeds = corpus()
    failures = []
    counts: dict[str, int] = {}
    t0 = time.perf_counter()
    k = 0
    with tempfile.TemporaryDirectory() as d:
        progress = Path(d) / "progress"
        while k < cases:
            progress.write_text("")
            # Files, not pipes: a worker that fills a pipe nobody reads yet would block and pass for a hang.
            out_path, err_path = Path(d) / "out", Path(d) / "err"
            with open(out_path, "w") as out_fh, open(err_path, "w") as err_fh:
                proc = subprocess.Popen([sys.executable, __file__, "--worker", "--seed", str(seed), "--start", str(k),
                                         "--stop", str(cases), "--progress", str(progress)],
                                        stdout=out_fh, stderr=err_fh, text=True)
            last, since, cpu_since = None, time.perf_counter(), 0.0
            hung = False
            while proc.poll() is None:
                time.sleep(0.05)
                now = progress.read_text().strip()
                cpu = cpu_seconds(proc.pid)
                if now != last:
                    last, since, cpu_since = now, time.perf_counter(), cpu
                elif now and now != "done" and (cpu - cpu_since > hang_s
                                                or time.perf_counter() - since > blocked_s):
                    proc.kill()
                    hung = True
                    break
            proc.wait()
            out, err = out_path.read_text(errors="replace"), err_path.read_text(errors="replace")
            for line in out.splitlines():
                rec = json.loads(line)
                if "counts" in rec:
                    for key, n in rec["counts"].items():
                        counts[key] = counts.get(key, 0) + n
                    continue
                folder = save_case(seed, rec["case"], "exception", rec["detail"], seeds, out_dir)
                failures.append({"case": rec["case"], "kind": "exception", "detail": rec["detail"], "saved": str(folder)})
                log(f"case {rec['case']}: {rec['detail']} -> {folder}")
            done = progress.read_text().strip()
            if done == "done" and proc.returncode == 0:
                break
            # The worker died or hung in case `done`: keep it and go on after it.
            bad = int(done) if done.isdigit() else k
            kind = "hang" if hung else f"crash{proc.returncode}"
            detail = f"over {hang_s:g} s of CPU time" if hung else (err.strip().splitlines() or ["(no output)"])[-1][:500]
            folder = save_case(seed, bad, kind, detail, seeds, out_dir)
            failures.append({"case": bad, "kind": kind, "detail": detail, "saved": str(folder)})
            log(f"case {bad}: {kind}: {detail} -> {folder}")
            k = bad + 1
    return {"seed": seed, "cases": cases, "seconds": round(time.perf_counter() - t0, 1), "failures": failures,
            "outcomes": dict(sorted(counts.items()))}


def replay(folder: Path) -> tuple[str, str]:
    """Runs a saved case in this process: ("ok" | "error" | "exception", detail)."""
    case = json.loads((folder / "case.json").read_text())
    files = {n: (folder / n).read_bytes() for n in case["files"]}
    with tempfile.TemporaryDirectory() as d:
        return run_files(case["target"], files, Path(d) / "case")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--cases", type=int, default=2000)
    ap.add_argument("--hang", type=float, default=HANG_S, help="seconds after which a case is a hang")
    ap.add_argument("--out", type=Path, default=CRASHES, help="where failing cases are kept")
    ap.add_argument("--replay", type=Path, help="run one saved case and print its outcome")
    ap.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--start", type=int, default=0, help=argparse.SUPPRESS)
    ap.add_argument("--stop", type=int, default=0, help=argparse.SUPPRESS)
    ap.add_argument("--progress", type=Path, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.worker:
        worker(args.seed, args.start, args.stop, args.progress)
        return 0
    if args.replay:
        outcome, detail = replay(args.replay)
        print(json.dumps({"outcome": outcome, "detail": detail}))
        return 0 if outcome != "exception" else 1
    result = fuzz(args.seed, args.cases, args.hang, args.out)
    print(f"fuzz: seed {result['seed']}, {result['cases']} cases in {result['seconds']} s, "
          f"{len(result['failures'])} failures; outcomes (target: ok = no error, error = TailorError): "
          + ", ".join(f"{k} {v}" for k, v in result["outcomes"].items()))
    return 1 if result["failures"] else 0


if __name__ == "__main__":
    sys.exit(main())
