"""Builds the installable Tailor extension: `dist/tailor_addon.zip`.

1. `maturin build` makes the abi3 `tailor` wheel (the native solver and its Python package);
2. the wheel is copied into `addon/tailor_addon/wheels/` (git-ignored), where the legacy
   add-on path (Blender 3.4 loading the folder directly) finds it too;
3. the add-on folder is staged under `build/addon/` with the manifest's `wheels = [...]` naming
   the wheel just built (its file name carries the version and platform tag, which vary);
4. Blender's own extension builder (`blender_ext.py build`, shipped inside the `bpy` wheel)
   validates the manifest and writes the zip, exactly as `blender --command extension build`.

Run with the project's .venv Python (it has maturin and bpy): `make addon`.

`--compat manylinux_2_28 --arch x86_64,aarch64` (`make addon-studio`) builds the wheels with
`maturin --zig` against glibc 2.28 (Rocky and Alma Linux 8, the studio baseline), one per
architecture, checks each library asks for no newer glibc symbol (`objdump -T`), and bundles
them all; Blender installs the wheel of its own platform. The default build (`make addon`) is
for this machine's glibc and architecture alone.
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


#: Blender's platform name of each architecture a wheel is built for.
PLATFORMS = {"x86_64": "linux-x64", "aarch64": "linux-arm64"}


def build_wheel(compat: str | None = None, arch: str | None = None) -> Path:
    """The abi3 wheel of the `tailor` module, built in release mode: for this machine, or with
    `compat` (a manylinux tag such as `manylinux_2_28`) for `arch` through `maturin --zig`,
    in a target folder of its own. (Not `--strip`: that changes the compiler flags and
    rebuilds every crate that `maturin develop` just built.)"""
    out = WHEEL_OUT / (arch or "native")
    shutil.rmtree(out, ignore_errors=True)
    env = dict(os.environ, VIRTUAL_ENV=str(Path(sys.prefix)))
    env["PATH"] = f"{Path(sys.prefix) / 'bin'}{os.pathsep}{env.get('PATH', '')}"
    cmd = [sys.executable, "-m", "maturin", "build", "--release", "--quiet", "-o", str(out)]
    if compat:
        cmd += ["--zig", "--compatibility", compat, "--target", f"{arch}-unknown-linux-gnu"]
        env["CARGO_TARGET_DIR"] = str(ROOT / "target" / f"{compat}-{arch}")
    subprocess.run(cmd, cwd=ROOT, env=env, check=True)
    wheels = sorted(out.glob("tailor-*.whl"))
    if len(wheels) != 1:
        sys.exit(f"build_addon: expected one tailor wheel in {out}, found {[w.name for w in wheels]}")
    if compat:
        check_glibc(wheels[0], compat)
    return wheels[0]


def newest_glibc(library: bytes) -> tuple[int, ...]:
    """The newest `GLIBC_x.y` symbol version `objdump -T` lists for a shared library."""
    import tempfile

    with tempfile.NamedTemporaryFile(suffix=".so") as f:
        f.write(library)
        f.flush()
        dump = subprocess.run(["objdump", "-T", f.name], capture_output=True, text=True, check=True).stdout
    versions = {tuple(int(v) for v in m.split(".")) for m in re.findall(r"GLIBC_(\d+(?:\.\d+)+)", dump)}
    return max(versions, default=(0,))


def check_glibc(wheel: Path, compat: str) -> None:
    """Refuses a wheel whose library needs a newer glibc than `compat` promises."""
    import zipfile

    promised = tuple(int(v) for v in re.fullmatch(r"manylinux_(\d+)_(\d+)", compat).groups())
    with zipfile.ZipFile(wheel) as z:
        for name in z.namelist():
            if name.endswith(".so"):
                needed = newest_glibc(z.read(name))
                if needed > promised:
                    sys.exit(f"build_addon: {wheel.name}: {name} needs GLIBC_{'.'.join(map(str, needed))}, "
                             f"newer than {compat} allows")
                print(f"build_addon: {wheel.name}: {name} needs at most GLIBC_{'.'.join(map(str, needed))}")


def bundle_wheels(wheels: list[Path]) -> list[Path]:
    """Copies the wheels into the add-on folder, replacing older ones."""
    WHEELS.mkdir(exist_ok=True)
    for old in WHEELS.glob("tailor-*.whl"):
        old.unlink()
    for wheel in wheels:
        shutil.copy2(wheel, WHEELS / wheel.name)
    return [WHEELS / w.name for w in wheels]


def stage(wheel_names: list[str], platforms: list[str] | None = None) -> Path:
    """A clean copy of the add-on with the manifest listing `wheel_names` (and `platforms`,
    when given)."""
    shutil.rmtree(STAGE, ignore_errors=True)
    staged = STAGE / ADDON.name
    shutil.copytree(ADDON, staged, ignore=shutil.ignore_patterns("__pycache__", "*.pyc", "_vendor"))
    manifest = staged / "blender_manifest.toml"
    text = manifest.read_text()
    listed = ", ".join(f'"./wheels/{name}"' for name in wheel_names)
    text, n = re.subn(r"(?m)^wheels\s*=\s*\[.*?\]", f"wheels = [{listed}]", text, flags=re.S)
    if n != 1:
        sys.exit(f"build_addon: {manifest} needs exactly one `wheels = [...]` line")
    if platforms:
        names = ", ".join(f'"{p}"' for p in platforms)
        text, n = re.subn(r"(?m)^platforms\s*=\s*\[.*?\]", f"platforms = [{names}]", text, flags=re.S)
        if n != 1:
            sys.exit(f"build_addon: {manifest} needs exactly one `platforms = [...]` line")
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
    ap.add_argument("--compat", metavar="TAG", help="build with maturin --zig for this manylinux tag (e.g. "
                                                     "manylinux_2_28: glibc 2.28, Rocky/Alma Linux 8)")
    ap.add_argument("--arch", default="x86_64", help="with --compat: architectures, comma-separated "
                                                      f"({', '.join(PLATFORMS)}; default x86_64)")
    args = ap.parse_args()
    platforms = None
    if args.wheel:
        wheels = [args.wheel.resolve()]
    elif args.compat:
        if not re.fullmatch(r"manylinux_\d+_\d+", args.compat):
            sys.exit(f"build_addon: --compat {args.compat!r}: expected a tag such as manylinux_2_28")
        archs = [a.strip() for a in args.arch.split(",") if a.strip()]
        unknown = [a for a in archs if a not in PLATFORMS]
        if unknown or not archs:
            sys.exit(f"build_addon: --arch {args.arch!r}: expected some of {', '.join(PLATFORMS)}")
        wheels = [build_wheel(args.compat, a) for a in archs]
        platforms = [PLATFORMS[a] for a in archs]
    else:
        wheels = [build_wheel()]
    bundled = bundle_wheels(wheels)
    build_zip(stage([b.name for b in bundled], platforms), args.output.resolve())
    names = ", ".join(b.name for b in bundled)
    print(f"build_addon: {args.output} ({args.output.stat().st_size / 1e6:.1f} MB, wheels {names})")


if __name__ == "__main__":
    main()
