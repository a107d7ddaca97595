"""``tailor batch`` (issue 26): many bakes on Ray, none lost.

The jobs are small (the sample skirt and T-shirt on the walking character, 20 preview frames,
no preroll: about a second each) so that the whole file runs in about a minute on 2 cores.
Ray is a test requirement (.ci/bootstrap installs it): without it these tests fail, they do not
skip. The two-node cluster is started here with ``ray start --block`` (one CPU each) in process
sessions of their own, and every process of those sessions is killed at the end, by id.
"""

from __future__ import annotations

import json
import os
import secrets
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest

import tailor

ROOT = Path(__file__).resolve().parent.parent
SAMPLES = ROOT / "sample_blends"
RAY = Path(sys.executable).with_name("ray")
MOTIONS = ["walk", "run", {"name": "walk-loop", "animation": "walk", "loop": True},
           {"name": "run-loop", "animation": "run", "loop": True}]
SETTINGS = {"frames": 20, "preset": "preview", "preroll": 0, "transition": 0}
#: The 8 jobs of the jobs file: 2 garments x 1 body x 4 motions.
NAMES = [f"{g}-character-{m if isinstance(m, str) else m['name']}" for g in ("skirt", "tshirt") for m in MOTIONS]


def env() -> dict:
    """The environment of every process here: the package importable by Ray's workers on every
    node, and one cluster token shared by the nodes and the driver (Ray 2.60 authenticates)."""
    package = str(Path(tailor.__file__).resolve().parent.parent)
    return dict(os.environ, PYTHONPATH=os.pathsep.join([package, os.environ.get("PYTHONPATH", "")]),
                RAY_USAGE_STATS_ENABLED="0", RAY_AUTH_MODE="token", RAY_AUTH_TOKEN=TOKEN)


TOKEN = secrets.token_hex(32)


def write_jobs(folder: Path, broken: bool) -> Path:
    doc = {"settings": SETTINGS, "outputs": ["cache"],
           "generate": {"patterns": [str(SAMPLES / "skirt.json"), str(SAMPLES / "tshirt.json")],
                        "bodies": str(SAMPLES / "character.glb"), "motions": MOTIONS}}
    if broken:
        # A garment file whose pieces are not a list: tailor simulate refuses it.
        (folder / "broken.json").write_text(json.dumps({"format": "tailor-garment", "version": 1, "pieces": 3}))
        doc["jobs"] = [{"name": "broken", "garment": "broken.json", "collider": str(SAMPLES / "character.glb")}]
    path = folder / ("jobs-broken.json" if broken else "jobs.json")
    path.write_text(json.dumps(doc))
    return path


def kill_session(sid: int) -> None:
    """SIGKILL every process of the session `sid` (a process this test started with a session
    of its own, and whatever it started: Ray's raylet, GCS and workers)."""
    ps = subprocess.run(["ps", "-eo", "pid=,sid="], capture_output=True, text=True).stdout
    for line in ps.splitlines():
        pid, s = map(int, line.split())
        if s == sid:
            try:
                os.kill(pid, signal.SIGKILL)
            except ProcessLookupError:
                pass


def batch(*args, **kw) -> subprocess.CompletedProcess:
    """`tailor batch ...` in a session of its own (a local Ray it starts dies with it)."""
    p = subprocess.Popen([sys.executable, "-m", "tailor", "batch", *map(str, args)], env=env(), text=True,
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, start_new_session=True, **kw)
    try:
        out, err = p.communicate(timeout=240)
    finally:
        kill_session(p.pid)
    return subprocess.CompletedProcess(p.args, p.returncode, out, err)


def events(out: Path) -> list[dict]:
    path = out / "batch.jsonl"
    return [json.loads(line) for line in path.read_text().splitlines()] if path.exists() else []


def caches(out: Path) -> dict[str, bytes]:
    return {n: (out / n / "garment.pc2").read_bytes() for n in NAMES}


def test_bad_jobs_files_are_one_line_errors(tmp_path):
    cases = {
        "notjson.json": ("{nope", "not a valid JSON file"),
        "unknown.json": (json.dumps({"jobz": []}), "unknown key(s) jobz"),
        "missing.json": (json.dumps({"jobs": [{"garment": "nowhere.json", "collider": "x.glb"}]}),
                         "nowhere.json is not a file"),
        "setting.json": (json.dumps({"settings": {"frames": 2, "presett": "preview"},
                                     "jobs": [{"garment": str(SAMPLES / "skirt.json"),
                                               "collider": str(SAMPLES / "character.glb")}]}),
                         "unknown setting(s) presett"),
        "choice.json": (json.dumps({"settings": {"frames": 2, "preset": "fast"},
                                    "jobs": [{"garment": str(SAMPLES / "skirt.json"),
                                              "collider": str(SAMPLES / "character.glb")}]}),
                        "invalid choice: 'fast'"),
    }
    for name, (text, message) in cases.items():
        (tmp_path / name).write_text(text)
        r = subprocess.run([sys.executable, "-m", "tailor", "batch", str(tmp_path / name), "--out",
                            str(tmp_path / "out")], capture_output=True, text=True, env=env())
        assert r.returncode == 2, (name, r.stderr)
        lines = r.stderr.strip().splitlines()
        assert len(lines) == 1 and lines[0].startswith("tailor batch: error: ") and name in lines[0], (name, r.stderr)
        assert message in lines[0], (name, lines[0])
        assert "Traceback" not in r.stderr


def test_generated_jobs_and_hashes(tmp_path):
    from tailor.batch import jobs as joblib

    jobs = joblib.load(write_jobs(tmp_path, broken=False))
    assert [j["name"] for j in jobs] == NAMES
    assert all(j["kind"] == "garment" and j["settings"] == SETTINGS for j in jobs)
    digests = {joblib.job_hash(j) for j in jobs}
    assert len(digests) == 8  # every job its own hash
    # A changed input file changes the hash: the job is not taken for done.
    skirt = tmp_path / "skirt"
    skirt.mkdir()
    for f in ("skirt.json", "skirt.bin"):
        (skirt / f).write_bytes((SAMPLES / f).read_bytes())
    job = dict(jobs[0], source=str(skirt / "skirt.json"))
    assert joblib.job_hash(job) == joblib.job_hash(jobs[0])  # the same contents elsewhere: the same job
    (skirt / "skirt.bin").write_bytes((SAMPLES / "skirt.bin").read_bytes()[:-4] + b"\0\0\0\0")
    joblib.file_sha256.__defaults__[0].clear()
    assert joblib.job_hash(job) != joblib.job_hash(jobs[0])


@pytest.fixture
def cluster(tmp_path):
    """A Ray cluster on this machine: a head and a second node (the one to kill), one CPU each,
    each `ray start --block` in its own session. Yields (address, the second node's id, its
    session)."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    address = f"127.0.0.1:{port}"
    started = []

    def start(args, log):
        p = subprocess.Popen([str(RAY), "start", "--block", "--num-cpus", "1", "--disable-usage-stats", *args],
                             env=env(), stdout=open(log, "w"), stderr=subprocess.STDOUT, start_new_session=True)
        started.append(p)
        deadline = time.time() + 90
        while "Ray runtime started" not in Path(log).read_text():
            assert p.poll() is None, f"ray start exited {p.returncode}: {Path(log).read_text()[-3000:]}"
            assert time.time() < deadline, f"ray start did not start: {Path(log).read_text()[-3000:]}"
            time.sleep(0.3)
        return p

    try:
        start(["--head", "--port", str(port), "--include-dashboard", "false"], tmp_path / "head.log")
        victim = start(["--address", address, "--resources", json.dumps({"victim": 1})], tmp_path / "victim.log")
        query = ("import ray, json; ray.init(address=%r, logging_level='ERROR'); "
                 "print(json.dumps([(n['NodeID'], 'victim' in n['Resources']) for n in ray.nodes() if n['Alive']]))"
                 % address)
        deadline = time.time() + 60
        while True:
            r = subprocess.run([sys.executable, "-c", query], env=env(), capture_output=True, text=True, timeout=60)
            nodes = json.loads(r.stdout.strip().splitlines()[-1]) if r.returncode == 0 and r.stdout.strip() else []
            if len(nodes) == 2:
                break
            assert time.time() < deadline, f"the cluster never had two nodes: {r.stdout} {r.stderr[-2000:]}"
            time.sleep(1)
        victim_id = next(n for n, v in nodes if v)
        yield address, victim_id, victim.pid
    finally:
        for p in reversed(started):
            kill_session(p.pid)
            p.wait(timeout=30)


def test_batch_local_then_cluster_with_a_killed_node(tmp_path, cluster):
    address, victim_id, victim_sid = cluster

    # 1. The 8 jobs and a broken one on a local Ray instance (no --address): the broken job is
    # tried twice and recorded failed, the 8 others finish.
    ref = tmp_path / "ref"
    r = batch(write_jobs(tmp_path, broken=True), "--out", ref, "--cpus", "2", "--retries", "1")
    assert r.returncode == 1, r.stdout + r.stderr
    assert "Traceback" not in r.stderr
    for n in NAMES:
        marker = json.loads((ref / n / "done.json").read_text())
        assert marker["status"] == "done" and marker["summary"]["frame"] == 20
        report = json.loads((ref / n / "report.json").read_text())
        assert report["complete"] and len(report["frames"]) == 20
    failed = json.loads((ref / "broken" / "failed.json").read_text())
    assert failed["attempts"] == 2 and "broken.json" in failed["error"] and "tailor simulate: error" in failed["error"]
    assert not (ref / "broken" / "done.json").exists()
    log = events(ref)
    assert [e["event"] for e in log if e.get("job") == "broken"] == ["submit", "retry", "submit", "failed"]
    assert sum(e["event"] == "done" for e in log) == 8
    # The summary table: every job with its verdict, the broken one with its error.
    table = r.stdout
    assert all(n in table for n in NAMES) and "FAILED" in table and "manifest" in table
    assert [row["name"] for row in json.loads((ref / "summary.json").read_text())] == ["broken", *NAMES]
    # Progress for people on stderr, with done, failed, running and time left.
    assert "9/9 jobs: 8 done, 1 failed, 0 running" in r.stderr and " left" in r.stderr

    # 2. A job's outputs are exactly what `tailor simulate` writes for it.
    direct = tmp_path / "direct"
    direct.mkdir()
    s = subprocess.run([sys.executable, "-m", "tailor", "simulate", str(SAMPLES / "tshirt.json"), "--collider",
                        str(SAMPLES / "character.glb"), "--animation", "run", "--loop", "-o", str(direct / "c.pc2"),
                        "--report", str(direct / "r.json"), "--frames", "20", "--preset", "preview", "--preroll",
                        "0", "--transition", "0"], env=env(), capture_output=True, text=True)
    assert s.returncode in (0, 3), s.stderr
    assert (direct / "c.pc2").read_bytes() == (ref / "tshirt-character-run-loop" / "garment.pc2").read_bytes()
    records = json.loads((direct / "r.json").read_text())["frames"]
    batch_records = json.loads((ref / "tshirt-character-run-loop" / "report.json").read_text())["frames"]
    strip = lambda rs: [{k: v for k, v in r.items() if k not in ("ms", "stages_ms")} for r in rs]  # noqa: E731
    assert strip(records) == strip(batch_records)

    # 3. Running the batch again does no work: no Ray, no job submitted, no file touched.
    stamps = {p: p.stat().st_mtime_ns for p in ref.rglob("*") if p.is_file() and p.name != "batch.jsonl"
              and p.name != "summary.json"}
    before = len(events(ref))
    t = time.time()
    again = batch(write_jobs(tmp_path, broken=True), "--out", ref, "--cpus", "2", "--retries", "1")
    assert again.returncode == 1  # the broken job stays failed (kept, not retried: --retry-failed would)
    assert "already done (nothing to run)" in again.stderr
    assert not [e for e in events(ref)[before:] if e["event"] in ("submit", "done", "retry", "failed")]
    assert {p: p.stat().st_mtime_ns for p in stamps} == stamps
    assert time.time() - t < 20

    # 4. The 8 jobs on the two-node cluster (--address); the second node is killed (every process
    # of it, raylet and workers) once it has finished a job and is running the next: its job is
    # rescheduled on the head and all 8 finish with the same caches as the local run.
    out = tmp_path / "cluster"
    p = subprocess.Popen([sys.executable, "-m", "tailor", "batch", str(write_jobs(tmp_path, broken=False)), "--out",
                          str(out), "--address", address, "--retries", "1"], env=env(), text=True,
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, start_new_session=True)
    killed_after = None
    try:
        deadline = time.time() + 180
        while p.poll() is None and killed_after is None:
            done = [e for e in events(out) if e["event"] == "done"]
            if any(e["node"] == victim_id for e in done):
                kill_session(victim_sid)
                killed_after = len(done)
            assert time.time() < deadline, "the victim node never finished a job"
            time.sleep(0.05)
        stdout, stderr = p.communicate(timeout=240)
    finally:
        kill_session(p.pid)
    assert killed_after is not None and killed_after < 8, "the node was not killed mid-run"
    assert p.returncode == 0, stdout + stderr
    log = events(out)
    done = [e for e in log if e["event"] == "done"]
    assert sorted(e["job"] for e in done) == sorted(NAMES)
    # After the kill, the jobs finished on the head node.
    assert all(e["node"] != victim_id for e in done[killed_after + 1:])
    assert caches(out) == caches(ref)


def test_without_ray_one_line(tmp_path):
    """Ray is not a dependency of the package: without it, a batch with work to do says so in one
    line (exit 2), no traceback."""
    jobs = write_jobs(tmp_path, broken=False)
    code = ("import sys; sys.modules['ray'] = None; from tailor import cli; "
            f"sys.exit(cli.main(['batch', {str(jobs)!r}, '--out', {str(tmp_path / 'out')!r}]))")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env())
    assert r.returncode == 2, r.stderr
    assert r.stderr.strip() == "tailor batch: error: tailor batch needs Ray: pip install ray"
    # And importing the package, the command line or the batch's modules imports no Ray.
    code = ("import sys; import tailor, tailor.cli, tailor.batch.jobs, tailor.batch.execute, tailor.batch.runner; "
            "tailor.cli.build_parser(); print('ray' in sys.modules)")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env())
    assert r.stdout.strip() == "False", r.stderr


def test_killed_batch_resumes_where_it_stopped(tmp_path):
    """The command itself killed (SIGKILL to it and its local Ray) after two jobs finished: the
    next run submits only the jobs not done, and every cache is the one of an uninterrupted batch."""
    jobs = write_jobs(tmp_path, broken=False)
    out = tmp_path / "out"
    p = subprocess.Popen([sys.executable, "-m", "tailor", "batch", str(jobs), "--out", str(out), "--cpus", "2"],
                         env=env(), text=True, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                         start_new_session=True)
    try:
        deadline = time.time() + 120
        while sum(e["event"] == "done" for e in events(out)) < 2:
            assert p.poll() is None, p.stderr.read()
            assert time.time() < deadline
            time.sleep(0.05)
    finally:
        kill_session(p.pid)
        p.wait()
    first = {e["job"] for e in events(out) if e["event"] == "done"}
    assert 2 <= len(first) < 8
    before = len(events(out))
    r = batch(jobs, "--out", out, "--cpus", "2")
    assert r.returncode == 0, r.stdout + r.stderr
    rerun = events(out)[before:]
    # The finished jobs were skipped; a job whose files were cut short by the kill has no marker
    # and runs again.
    assert {e["job"] for e in rerun if e["event"] == "skip"} == first
    assert {e["job"] for e in rerun if e["event"] == "submit"} == set(NAMES) - first
    assert sorted(e["job"] for e in rerun if e["event"] == "done") == sorted(set(NAMES) - first)
    assert r.stdout.count(" *") == len(first)
    # The same caches as an uninterrupted batch of the same jobs.
    again = tmp_path / "again"
    r = batch(jobs, "--out", again, "--cpus", "2")
    assert r.returncode == 0
    assert caches(out) == caches(again)


def test_pattern_job_is_import_then_simulate(tmp_path):
    """A pattern job (GarmentCode here) runs `tailor import` then `tailor simulate` on its garment,
    as the two commands would (the function a Ray task calls, run here without Ray)."""
    from tailor.batch import jobs as joblib
    from tailor.batch.execute import execute

    pattern = ROOT / "native/tailor-core/tests/data/garmentcode/dress_pencil_specification.json"
    (tmp_path / "jobs.json").write_text(json.dumps({"settings": {**SETTINGS, "frames": 3}, "jobs": [
        {"name": "dress", "pattern": str(pattern), "import": {"edge": 0.05}, "collider": str(SAMPLES / "character.glb"),
         "outputs": ["cache", "garment", "obj"]}]}))
    [job] = joblib.load(tmp_path / "jobs.json")
    files = joblib.inputs(job)
    result = execute(job, [(r, os.path.basename(p)) for r, p in files], [Path(p).read_bytes() for _, p in files], 1)
    assert result["ok"], result
    stem = pattern.stem
    assert {f"garment/{stem}.json", f"garment/{stem}.bin", "garment.pc2", "report.json", "simulate.log",
            f"obj/{stem}.0003.obj"} <= set(result["files"])
    assert str(tmp_path) not in result["files"]["simulate.log"].decode() and "tailor-batch-" not in \
        result["files"]["simulate.log"].decode()

    def cli(*args):
        r = subprocess.run([sys.executable, "-m", "tailor", *map(str, args)], env=env(), capture_output=True, text=True)
        assert r.returncode in (0, 3), r.stderr

    cli("import", pattern, "--edge", "0.05", "-o", tmp_path / f"{stem}.json")
    cli("simulate", tmp_path / f"{stem}.json", "--collider", SAMPLES / "character.glb", "--frames", 3, "--preset",
        "preview", "--preroll", 0, "--transition", 0, "--report", tmp_path / "r.json", "-o", tmp_path / "c.pc2",
        "--threads", 1)
    assert (tmp_path / "c.pc2").read_bytes() == result["files"]["garment.pc2"]
    assert (tmp_path / f"{stem}.bin").read_bytes() == result["files"][f"garment/{stem}.bin"]
