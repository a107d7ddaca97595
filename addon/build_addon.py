"""Builds the installable Tailor extension: `dist/tailor_addon.zip`.

1. `maturin build` makes the abi3 `tailor` wheel (the native solver and its Python package);
2. the wheel is copied into `addon/tailor_addon/wheels/` (git-ignored), where the legacy
   add-on path (Blender 3.4 loading the folder directly) finds it too;
3. the add-on folder is staged under `build/addon/` with the manifest's `wheels = [...]` naming
   the wheel just built (its file name carries the version and platform tag, which vary);
4. Blender's own extension builder (`blender_ext.py build`, shipped inside the `bpy` wheel)
   validates the manifest and writes the zip, exactly as `blender --command extension build`.

Run with the project's .venv Python (it has maturin and bpy): `make addon`.
"""

from __future__ import annotations

import argparse
import importlib.util
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
ADDON = ROOT / "addon" / "tailor_addon"
WHEELS = ADDON / "wheels"
STAGE = ROOT / "build" / "addon"
WHEEL_OUT = ROOT / "build" / "wheels"


def build_wheel() -> Path:
    """The abi3 wheel of the `tailor` module, built in release mode. (Not `--strip`: that
    changes the compiler flags and rebuilds every crate that `maturin develop` just built.)"""
    shutil.rmtree(WHEEL_OUT, ignore_errors=True)
    env = dict(os.environ, VIRTUAL_ENV=str(Path(sys.prefix)))
    env["PATH"] = f"{Path(sys.prefix) / 'bin'}{os.pathsep}{env.get('PATH', '')}"
    cmd = [sys.executable, "-m", "maturin", "build", "--release", "--quiet", "-o", str(WHEEL_OUT)]
    subprocess.run(cmd, cwd=ROOT, env=env, check=True)
    wheels = sorted(WHEEL_OUT.glob("tailor-*.whl"))
    if len(wheels) != 1:
        sys.exit(f"build_addon: expected one tailor wheel in {WHEEL_OUT}, found {[w.name for w in wheels]}")
    return wheels[0]


def bundle_wheel(wheel: Path) -> Path:
    """Copies the wheel into the add-on folder, replacing older ones."""
    WHEELS.mkdir(exist_ok=True)
    for old in WHEELS.glob("tailor-*.whl"):
        old.unlink()
    target = WHEELS / wheel.name
    shutil.copy2(wheel, target)
    return target


def stage(wheel_name: str) -> Path:
    """A clean copy of the add-on with the manifest listing `wheel_name`."""
    shutil.rmtree(STAGE, ignore_errors=True)
    staged = STAGE / ADDON.name
    shutil.copytree(ADDON, staged, ignore=shutil.ignore_patterns("__pycache__", "*.pyc", "_vendor"))
    manifest = staged / "blender_manifest.toml"
    text = manifest.read_text()
    text, n = re.subn(r"(?m)^wheels\s*=\s*\[.*?\]", f'wheels = ["./wheels/{wheel_name}"]', text, flags=re.S)
    if n != 1:
        sys.exit(f"build_addon: {manifest} needs exactly one `wheels = [...]` line")
    manifest.write_text(text)
    return staged


def extension_builder() -> Path:
    """`blender_ext.py` of the installed `bpy` wheel (Blender's extension command line)."""
    spec = importlib.util.find_spec("bpy")
    if spec is None or not spec.submodule_search_locations:
        sys.exit("build_addon: the bpy wheel is not installed in this Python (run `make setup`)")
    base = Path(list(spec.submodule_search_locations)[0])
    found = sorted(base.glob("*/scripts/addons_core/bl_pkg/cli/blender_ext.py"))
    if not found:
        sys.exit(f"build_addon: Blender's extension builder not found under {base}")
    return found[-1]


def build_zip(staged: Path, output: Path) -> None:
    output.parent.mkdir(parents=True, exist_ok=True)
    if output.exists():
        output.unlink()
    cmd = [
        sys.executable,
        str(extension_builder()),
        "build",
        "--source-dir",
        str(staged),
        "--output-filepath",
        str(output),
    ]
    run = subprocess.run(cmd, capture_output=True, text=True)
    if run.returncode != 0:
        sys.exit(f"build_addon: Blender's extension builder failed:\n{run.stdout}{run.stderr}")
    if not output.is_file():
        sys.exit(f"build_addon: the extension builder wrote no {output}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-o", "--output", type=Path, default=ROOT / "dist" / "tailor_addon.zip")
    ap.add_argument("--wheel", type=Path, help="use this tailor wheel instead of building one (e.g. a CI artifact)")
    args = ap.parse_args()
    wheel = args.wheel.resolve() if args.wheel else build_wheel()
    bundled = bundle_wheel(wheel)
    build_zip(stage(bundled.name), args.output.resolve())
    print(f"build_addon: {args.output} ({args.output.stat().st_size / 1e6:.1f} MB, wheel {bundled.name})")


if __name__ == "__main__":
    main()
