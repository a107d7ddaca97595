"""The JOBS file of ``tailor batch``, each job's input hash, and its outputs on disk.

A JOBS file is JSON (or TOML when it ends in ``.toml``); paths in it are relative to its folder::

    {"settings": {"frames": 90, "preset": "final"},      # defaults of every job (simulate's options)
     "outputs": ["cache"],                                 # defaults: any of cache, usd, obj, garment
     "jobs": [{"name": "skirt-walk", "garment": "skirt.json", "collider": "body.glb",
               "animation": "walk", "settings": {"frames": 30}},
              {"pattern": "dress_specification.json", "import": {"edge": 0.02}, "collider": "body.glb"}],
     "generate": [{"patterns": "patterns/", "bodies": ["body_a.glb", "body_b.glb"],
                   "motions": ["walk", {"name": "run-loop", "animation": "run", "loop": true}]}]}

A job is a garment file (``garment``) or a pattern (``pattern``: DXF, SVG or GarmentCode JSON,
imported first as ``tailor import`` would, with the ``import`` options ``edge``, ``size``,
``units``), a ``collider`` and its motion (``animation``, ``collider_anim``, ``loop``), the
``settings`` (``tailor simulate``'s options by name, ``assemble_at`` for ``--assemble-at``; a true
boolean is its flag) and the ``outputs``. ``generate`` makes one job for every pattern or garment
file in a folder x every body x every motion (a motion is a clip's name or a dict with
``name``, ``animation``, ``collider_anim``, ``loop``), named ``PATTERN-BODY-MOTION``.

Every job's command line is checked by ``tailor simulate``'s own parser when the file is read, so
a misspelt setting is an error naming the file and the job before any work starts.

A job is done when its folder ``DIR/NAME/`` holds ``done.json`` (written last, atomically) whose
``hash`` is the job's: a SHA-256 of the job as written (settings, outputs, motion) and of the
contents of its input files (garment and sidecar or pattern, collider, collider cache), so a
changed input or setting runs the job again and anything else is never redone. A job that failed
all its tries holds ``failed.json`` with the same hash and its error instead.
"""

from __future__ import annotations

import hashlib
import json
import os
import uuid
from pathlib import Path

#: Marker of a finished job, written last in its folder.
DONE = "done.json"
#: Marker of a job that failed every try (its error), so that a rerun does not redo it by default.
FAILED = "failed.json"
#: What a job may write besides its report and log: the flag of ``tailor simulate`` (or ``import``)
#: and the file (or folder) inside the job's folder.
OUTPUTS = {"cache": "garment.pc2", "usd": "garment.usd", "obj": "obj", "garment": "garment"}
REPORT = "report.json"
LOG = "simulate.log"

_JOB_KEYS = {"name", "garment", "pattern", "import", "collider", "collider_anim", "animation", "loop", "settings",
             "outputs"}
_IMPORT_KEYS = {"edge", "size", "units"}
_MOTION_KEYS = {"name", "animation", "collider_anim", "loop"}
_PATTERN_SUFFIXES = (".json", ".dxf", ".svg")
_BODY_SUFFIXES = (".obj", ".ply", ".glb", ".gltf")


class JobsError(ValueError):
    """A JOBS file that cannot be read or says something wrong; the message names the file."""


def load(path: str | os.PathLike) -> list[dict]:
    """The jobs of the JOBS file at `path`, each a dict with absolute paths and a unique `name`,
    in the file's order (explicit jobs, then generated ones)."""
    path = Path(path)
    try:
        text = path.read_bytes()
    except OSError as exc:
        raise JobsError(f"{path}: cannot be read ({exc.strerror or exc})") from None
    try:
        if path.suffix.lower() == ".toml":
            import tomllib

            doc = tomllib.loads(text.decode())
        else:
            doc = json.loads(text)
    except (ValueError, UnicodeDecodeError) as exc:
        raise JobsError(f"{path}: not a valid {'TOML' if path.suffix.lower() == '.toml' else 'JSON'} file ({exc})") \
            from None
    where = str(path)
    if not isinstance(doc, dict):
        raise JobsError(f"{where}: the top level must be an object with 'jobs' and/or 'generate'")
    unknown = set(doc) - {"settings", "outputs", "jobs", "generate"}
    if unknown:
        raise JobsError(f"{where}: unknown key(s) {', '.join(sorted(unknown))} (known: settings, outputs, jobs, "
                        f"generate)")
    base = path.parent
    defaults = {"settings": _mapping(doc.get("settings", {}), f"{where}: settings"),
                "outputs": doc.get("outputs", ["cache"])}
    jobs = []
    explicit = doc.get("jobs", [])
    if not isinstance(explicit, list):
        raise JobsError(f"{where}: 'jobs' must be a list")
    for i, raw in enumerate(explicit):
        jobs.append(_job(raw, base, defaults, f"{where}: jobs[{i}]"))
    generate = doc.get("generate", [])
    for i, gen in enumerate(generate if isinstance(generate, list) else [generate]):
        jobs.extend(_generate(gen, base, defaults, f"{where}: generate[{i}]"))
    if not jobs:
        raise JobsError(f"{where}: no jobs (give 'jobs' or 'generate')")
    seen: dict[str, int] = {}
    for job in jobs:
        if job["name"] in seen:
            raise JobsError(f"{where}: two jobs are named {job['name']!r} (each job writes into DIR/NAME)")
        seen[job["name"]] = 1
    for job in jobs:
        check_arguments(job, where)
    return jobs


def _mapping(value, where: str) -> dict:
    if not isinstance(value, dict):
        raise JobsError(f"{where} must be an object")
    return value


def _path(value, base: Path, where: str) -> str:
    if not isinstance(value, str) or not value:
        raise JobsError(f"{where} must be a path")
    p = (base / value).resolve()
    if not p.is_file():
        raise JobsError(f"{where}: {value} is not a file")
    return str(p)


def _safe_name(name, where: str) -> str:
    if not isinstance(name, str) or not name or name.startswith(".") or any(
            c in name for c in '/\\:*?"<>|\0') or len(name) > 200:
        raise JobsError(f"{where}: name {name!r} is not usable as a folder name")
    return name


def _job(raw, base: Path, defaults: dict, where: str) -> dict:
    raw = _mapping(raw, where)
    unknown = set(raw) - _JOB_KEYS
    if unknown:
        raise JobsError(f"{where}: unknown key(s) {', '.join(sorted(unknown))} (known: {', '.join(sorted(_JOB_KEYS))})")
    if ("garment" in raw) == ("pattern" in raw):
        raise JobsError(f"{where}: give exactly one of 'garment' (a garment file) or 'pattern' (DXF, SVG, GarmentCode)")
    if "collider" not in raw:
        raise JobsError(f"{where}: no 'collider'")
    kind = "garment" if "garment" in raw else "pattern"
    source = _path(raw[kind], base, f"{where}.{kind}")
    job = {"kind": kind, "source": source, "collider": _path(raw["collider"], base, f"{where}.collider"),
           "collider_anim": _path(raw["collider_anim"], base, f"{where}.collider_anim") if raw.get("collider_anim")
           else None,
           "animation": raw.get("animation"), "loop": bool(raw.get("loop", False))}
    imp = _mapping(raw.get("import", {}), f"{where}.import")
    if set(imp) - _IMPORT_KEYS:
        raise JobsError(f"{where}.import: unknown key(s) {', '.join(sorted(set(imp) - _IMPORT_KEYS))} "
                        f"(known: edge, size, units)")
    if imp and kind != "pattern":
        raise JobsError(f"{where}: 'import' options belong to a 'pattern' job")
    job["import"] = imp
    job["settings"] = {**defaults["settings"], **_mapping(raw.get("settings", {}), f"{where}.settings")}
    outputs = raw.get("outputs", defaults["outputs"])
    if not isinstance(outputs, list) or set(outputs) - set(OUTPUTS):
        raise JobsError(f"{where}: outputs must be a list of {', '.join(OUTPUTS)} (got {outputs!r})")
    if "garment" in outputs and kind != "pattern":
        raise JobsError(f"{where}: the 'garment' output is the imported garment file of a 'pattern' job")
    job["outputs"] = sorted(set(outputs))
    name = raw.get("name") or Path(source).stem + "-" + Path(job["collider"]).stem
    job["name"] = _safe_name(name, where)
    return job


def _folder_files(value, base: Path, suffixes, where: str) -> list[Path]:
    """A folder's files with these suffixes (sorted), a list of files, or one file."""
    items = value if isinstance(value, list) else [value]
    out = []
    for item in items:
        if not isinstance(item, str):
            raise JobsError(f"{where} must be a folder, a file or a list of files")
        p = (base / item).resolve()
        if p.is_dir():
            found = sorted(f for f in p.iterdir() if f.is_file() and f.suffix.lower() in suffixes)
            if not found:
                raise JobsError(f"{where}: {item} holds no {', '.join(suffixes)} file")
            out.extend(found)
        elif p.is_file():
            out.append(p)
        else:
            raise JobsError(f"{where}: {item} is neither a folder nor a file")
    return out


def is_garment_file(path: str | os.PathLike) -> bool:
    """Whether a .json file is a Tailor garment file (``"format": "tailor-garment"``) rather than
    a GarmentCode pattern."""
    if Path(path).suffix.lower() != ".json":
        return False
    try:
        with open(path, "rb") as fh:
            return json.load(fh).get("format") == "tailor-garment"
    except (OSError, ValueError, AttributeError):
        return False


def _generate(gen, base: Path, defaults: dict, where: str) -> list[dict]:
    gen = _mapping(gen, where)
    unknown = set(gen) - {"patterns", "bodies", "motions", "settings", "outputs", "import"}
    if unknown:
        raise JobsError(f"{where}: unknown key(s) {', '.join(sorted(unknown))} (known: patterns, bodies, motions, "
                        f"settings, outputs, import)")
    for key in ("patterns", "bodies"):
        if key not in gen:
            raise JobsError(f"{where}: no '{key}'")
    patterns = _folder_files(gen["patterns"], base, _PATTERN_SUFFIXES, f"{where}.patterns")
    bodies = _folder_files(gen["bodies"], base, _BODY_SUFFIXES, f"{where}.bodies")
    motions = []
    for j, m in enumerate(gen.get("motions") or [{}]):
        m = {"name": m, "animation": m} if isinstance(m, str) else _mapping(m, f"{where}.motions[{j}]")
        if set(m) - _MOTION_KEYS:
            raise JobsError(f"{where}.motions[{j}]: unknown key(s) {', '.join(sorted(set(m) - _MOTION_KEYS))} "
                            f"(known: {', '.join(sorted(_MOTION_KEYS))})")
        motions.append(m)
    jobs = []
    for p in patterns:
        kind = "garment" if is_garment_file(p) else "pattern"
        for b in bodies:
            for j, m in enumerate(motions):
                motion_name = m.get("name") or m.get("animation") or (Path(m["collider_anim"]).stem
                                                                       if m.get("collider_anim") else "default")
                raw = {"name": f"{p.stem}-{b.stem}-{motion_name}", kind: str(p), "collider": str(b),
                       **{k: v for k, v in m.items() if k != "name"}}
                if kind == "pattern" and gen.get("import"):
                    raw["import"] = gen["import"]
                if "settings" in gen:
                    raw["settings"] = gen["settings"]
                if "outputs" in gen:
                    raw["outputs"] = [o for o in gen["outputs"] if kind == "pattern" or o != "garment"]
                jobs.append(_job(raw, base, defaults, f"{where} ({p.name} x {b.name} x motion {j})"))
    return jobs


def simulate_argv(job: dict, garment: str, collider: str, collider_anim: str | None, out: str,
                  threads: int | None) -> list[str]:
    """The ``tailor`` command line of the job's simulation (``simulate GARMENT --collider ...``),
    its report and outputs written into the folder `out`."""
    argv = ["simulate", garment, "--collider", collider, "--report", os.path.join(out, REPORT)]
    if collider_anim:
        argv += ["--collider-anim", collider_anim]
    if job.get("animation"):
        argv += ["--animation", str(job["animation"])]
    if job.get("loop"):
        argv += ["--loop"]
    if "cache" in job["outputs"]:
        argv += ["-o", os.path.join(out, OUTPUTS["cache"])]
    if "usd" in job["outputs"]:
        argv += ["--usd", os.path.join(out, OUTPUTS["usd"])]
    if "obj" in job["outputs"]:
        argv += ["--obj-dir", os.path.join(out, OUTPUTS["obj"])]
    for key, value in job["settings"].items():
        flag = "--" + str(key).replace("_", "-")
        if isinstance(value, bool):
            argv += [flag] if value else []
        else:
            argv += [flag, str(value)]
    if threads:
        argv += ["--threads", str(threads)]
    return argv


def import_argv(job: dict, pattern: str, garment: str) -> list[str]:
    """The ``tailor import`` command line that turns a pattern job's pattern into `garment`."""
    argv = ["import", pattern, "-o", garment]
    for key, value in job["import"].items():
        argv += ["--" + key, str(value)]
    return argv


class _ArgumentError(Exception):
    pass


def parse(argv: list[str]):
    """``argv`` parsed by the ``tailor`` command line's own parser, its error raised as an
    exception (the command line's parser would exit)."""
    from tailor import cli

    class Parser(cli._Parser):
        def error(self, message):
            raise _ArgumentError(message)

    parser = Parser(prog="tailor")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=Parser)
    from tailor.commands import import_, simulate

    import_.register(sub)
    simulate.register(sub)
    return parser.parse_args(argv)


#: ``tailor simulate``'s options that a job gives by its own keys or the batch decides, not settings.
_NOT_SETTINGS = {"collider", "collider_anim", "animation", "loop", "report", "output", "usd", "obj_dir", "resume",
                 "threads", "help"}


def settings_known() -> set[str]:
    """The names a job's ``settings`` may use: ``tailor simulate``'s options (``--assemble-at`` is
    ``assemble_at``) but those the job or the batch sets."""
    import argparse

    from tailor.commands import simulate

    sub = argparse.ArgumentParser().add_subparsers()
    simulate.register(sub)
    parser = sub.choices["simulate"]
    return {a.dest for a in parser._actions if a.option_strings} - _NOT_SETTINGS


def check_arguments(job: dict, where: str) -> None:
    """Parses the job's command lines with the command line's parser (settings by name, types,
    choices), so a bad setting fails when the JOBS file is read."""
    unknown = set(job["settings"]) - settings_known()
    if unknown:
        raise JobsError(f"{where}: job {job['name']!r}: unknown setting(s) {', '.join(sorted(unknown))} (known: "
                        f"{', '.join(sorted(settings_known()))})")
    argvs = [simulate_argv(job, "GARMENT.json", "COLLIDER", None, "OUT", None)]
    if job["kind"] == "pattern":
        argvs.append(import_argv(job, "PATTERN", "GARMENT.json"))
    for argv in argvs:
        try:
            parse(argv)
        except _ArgumentError as exc:
            raise JobsError(f"{where}: job {job['name']!r}: {argv[0]}: {exc}") from None
        except SystemExit:  # --help and the like: never meant as a setting
            raise JobsError(f"{where}: job {job['name']!r}: bad settings {argv[4:]}") from None


def inputs(job: dict) -> list[tuple[str, str]]:
    """(role, path) of every file the job reads: the garment file and its sidecar or the pattern,
    the collider and its cache."""
    import tailor

    out = [(job["kind"], job["source"])]
    if job["kind"] == "garment":
        sidecar = os.fspath(tailor.sidecar_path(job["source"]))
        if os.path.exists(sidecar):
            out.append(("sidecar", sidecar))
    out.append(("collider", job["collider"]))
    if job["collider_anim"]:
        out.append(("collider_anim", job["collider_anim"]))
    return out


def file_sha256(path: str, _cache: dict[str, str] = {}) -> str:  # noqa: B006 - one cache per process, by design
    """SHA-256 of a file's contents (remembered per path within a process: thousands of jobs share
    a few bodies)."""
    if path not in _cache:
        h = hashlib.sha256()
        with open(path, "rb") as fh:
            for chunk in iter(lambda: fh.read(1 << 20), b""):
                h.update(chunk)
        _cache[path] = h.hexdigest()
    return _cache[path]


def job_hash(job: dict) -> str:
    """The hash that marks the job done: its spec (paths replaced by file names and their
    contents' hashes, so moving the inputs keeps the batch done) and its inputs' contents."""
    spec = {k: v for k, v in job.items() if k not in ("source", "collider", "collider_anim")}
    spec["inputs"] = [(role, os.path.basename(p), file_sha256(p)) for role, p in inputs(job)]
    return hashlib.sha256(json.dumps(spec, sort_keys=True).encode()).hexdigest()


def read_marker(folder: Path, name: str) -> dict | None:
    try:
        with open(folder / name) as fh:
            doc = json.load(fh)
        return doc if isinstance(doc, dict) else None
    except (OSError, ValueError):
        return None


def is_done(folder: Path, digest: str) -> dict | None:
    """The job's done marker when it matches `digest` and every file it lists is there with its
    size, else None."""
    marker = read_marker(folder, DONE)
    if not marker or marker.get("hash") != digest:
        return None
    for rel, size in marker.get("files", {}).items():
        p = folder / rel
        if not p.is_file() or p.stat().st_size != size:
            return None
    return marker


def write_atomic(path: Path, data: bytes) -> None:
    """`data` into a temporary file beside `path`, then renamed over it: a reader (or a batch
    killed meanwhile) sees the old file or the new one, never half of one."""
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.name}.{uuid.uuid4().hex[:8]}.tmp")
    try:
        with open(tmp, "wb") as fh:
            fh.write(data)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    finally:
        if tmp.exists():
            tmp.unlink()


def write_done(folder: Path, digest: str, files: dict[str, bytes], record: dict) -> dict:
    """A finished job's files, each atomically, then its done marker (last: a job killed while
    its files are written is not done). Returns the marker."""
    (folder / FAILED).unlink(missing_ok=True)
    (folder / DONE).unlink(missing_ok=True)  # an older run's marker must not vouch for new files
    for rel, data in sorted(files.items()):
        write_atomic(folder / rel, data)
    marker = {"hash": digest, **record, "files": {rel: len(data) for rel, data in files.items()}}
    write_atomic(folder / DONE, json.dumps(marker, indent=1).encode())
    return marker


def write_failed(folder: Path, digest: str, record: dict) -> dict:
    marker = {"hash": digest, **record}
    write_atomic(folder / FAILED, json.dumps(marker, indent=1).encode())
    return marker
