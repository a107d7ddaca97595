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
architecture, checks each library asks for no newer glibc symbol (`objdump -T`) and that PyPA's
`auditwheel show` finds the wheel consistent with that tag (its policy of libraries too), and bundles
them all; Blender installs the wheel of its own platform. The default build (`make addon`) is
for this machine's glibc and architecture alone.

`--wheel W [--wheel W2 ...]` bundles wheels built elsewhere (the release workflow's matrix,
`.github/workflows/release.yml`: Linux, Windows and macOS runners), the manifest's platforms
read from the wheels' tags ([`blender_platform`]); with `--split-platforms` the output is a
folder with one zip per platform (Blender's `build --split-platforms`), each carrying only its
platform's wheel.
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

#: A wheel's platform tag (its file name's last field) -> Blender's platform name: each pattern
#: is matched against the whole tag (PEP 425/600; macOS tags carry the minimum OS version).
WHEEL_PLATFORMS = [
    (r"(many|musl)linux_\d+_\d+_x86_64|manylinux(1|2010|2014)_x86_64|linux_x86_64", "linux-x64"),
    (r"(many|musl)linux_\d+_\d+_aarch64|manylinux2014_aarch64|linux_aarch64", "linux-arm64"),
    (r"win_amd64", "windows-x64"),
    (r"win_arm64", "windows-arm64"),
    (r"macosx_\d+_\d+_x86_64", "macos-x64"),
    (r"macosx_\d+_\d+_arm64", "macos-arm64"),
]


def blender_platform(wheel_name: str) -> str:
    """Blender's platform name (`linux-x64`, `windows-x64`, `macos-arm64`, ...) of a wheel, from
    the platform tag of its file name; a wheel for more than one platform, or for none Blender
    knows, is an error (a universal2 macOS wheel would have to be listed under both)."""
    stem = wheel_name.removesuffix(".whl")
    parts = stem.split("-")
    if len(parts) < 5 or not wheel_name.endswith(".whl"):
        sys.exit(f"build_addon: {wheel_name!r} is not a wheel file name (NAME-VERSION-PY-ABI-PLATFORM.whl)")
    found = {blender for tag in parts[-1].split(".") for pattern, blender in WHEEL_PLATFORMS
             if re.fullmatch(pattern, tag)}
    if len(found) != 1:
        sys.exit(f"build_addon: {wheel_name}: platform tag {parts[-1]!r} names "
                 f"{'no platform Blender knows' if not found else 'several platforms: ' + ', '.join(sorted(found))}")
    return found.pop()


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
        check_auditwheel(wheels[0], compat, arch)
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


def auditwheel_tag(report: str) -> tuple[tuple[int, int], str] | None:
    """The most compatible platform tag `auditwheel show` finds a wheel consistent with, as
    ((major, minor), arch), from its report; None when it names none (not a manylinux wheel)."""
    text = re.sub(r"\s+", " ", report)  # auditwheel wraps its report at any word
    m = re.search(r'consistent with the following platform tag: "manylinux_(\d+)_(\d+)_(\w+)"', text)
    return ((int(m.group(1)), int(m.group(2))), m.group(3)) if m else None


def check_auditwheel(wheel: Path, compat: str, arch: str) -> None:
    """Refuses a wheel that PyPA's `auditwheel show` does not find consistent with `compat` for
    `arch`: besides glibc's symbols it checks every library the wheel links against the
    manylinux policy (a library a studio machine may lack), which `objdump -T` does not."""
    run = subprocess.run([sys.executable, "-m", "auditwheel", "show", str(wheel)], capture_output=True, text=True)
    if run.returncode != 0:
        sys.exit(f"build_addon: auditwheel show {wheel.name} failed (pip install auditwheel): "
                 f"{(run.stderr or run.stdout).strip().splitlines()[-1:]}")
    found = auditwheel_tag(run.stdout)
    promised = tuple(int(v) for v in re.fullmatch(r"manylinux_(\d+)_(\d+)", compat).groups())
    if found is None or found[0] > promised or found[1] != arch:
        sys.exit(f"build_addon: {wheel.name}: auditwheel finds it consistent with "
                 f"{'no manylinux tag' if found is None else f'manylinux_{found[0][0]}_{found[0][1]}_{found[1]}'}, "
                 f"not {compat}_{arch}")
    print(f"build_addon: {wheel.name}: auditwheel: consistent with manylinux_{found[0][0]}_{found[0][1]}_{found[1]}")


def bundle_wheels(wheels: list[Path], into: Path = WHEELS) -> list[Path]:
    """Copies the wheels into the add-on's `wheels/` folder, replacing older ones."""
    into.mkdir(exist_ok=True)
    for old in into.glob("tailor-*.whl"):
        old.unlink()
    for wheel in wheels:
        shutil.copy2(wheel, into / wheel.name)
    return [into / w.name for w in wheels]


def stage(wheel_names: list[str], platforms: list[str] | None = None, addon: Path = ADDON,
          stage_dir: Path = STAGE) -> Path:
    """A clean copy of the add-on under `stage_dir` with the manifest listing `wheel_names`
    (and `platforms`, when given)."""
    shutil.rmtree(stage_dir, ignore_errors=True)
    staged = stage_dir / addon.name
    shutil.copytree(addon, staged, ignore=shutil.ignore_patterns("__pycache__", "*.pyc", "_vendor"))
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


def build_zip(staged: Path, output: Path, split: bool = False) -> list[Path]:
    """The extension zip at `output`; with `split`, one zip a platform in the folder `output`
    (Blender names each `tailor-VERSION-PLATFORM.zip`). Returns the zips written."""
    if split:
        shutil.rmtree(output, ignore_errors=True)
        output.mkdir(parents=True)
        where = ["--split-platforms", "--output-dir", str(output)]
    else:
        output.parent.mkdir(parents=True, exist_ok=True)
        if output.exists():
            output.unlink()
        where = ["--output-filepath", str(output)]
    cmd = [sys.executable, str(extension_builder()), "build", "--source-dir", str(staged), *where]
    run = subprocess.run(cmd, capture_output=True, text=True)
    if run.returncode != 0:
        sys.exit(f"build_addon: Blender's extension builder failed:\n{run.stdout}{run.stderr}")
    zips = sorted(output.glob("*.zip")) if split else [output] if output.is_file() else []
    if not zips:
        sys.exit(f"build_addon: the extension builder wrote no zip at {output}")
    return zips


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-o", "--output", type=Path, default=ROOT / "dist" / "tailor_addon.zip")
    ap.add_argument("--wheel", type=Path, action="append", help="use this tailor wheel instead of building one (e.g. "
                    "a CI artifact); repeat for several platforms (the manifest's platforms from their tags)")
    ap.add_argument("--split-platforms", action="store_true", help="write one zip per platform into the folder "
                    "given by -o (default dist/extensions)")
    ap.add_argument("--compat", metavar="TAG", help="build with maturin --zig for this manylinux tag (e.g. "
                                                     "manylinux_2_28: glibc 2.28, Rocky/Alma Linux 8)")
    ap.add_argument("--arch", default="x86_64", help="with --compat: architectures, comma-separated "
                                                      f"({', '.join(PLATFORMS)}; default x86_64)")
    args = ap.parse_args()
    platforms = None
    if args.wheel:
        wheels = [w.resolve() for w in args.wheel]
        missing = [str(w) for w in wheels if not w.is_file()]
        if missing:
            sys.exit(f"build_addon: no such wheel: {', '.join(missing)}")
        by_platform: dict[str, str] = {}
        for w in wheels:
            p = blender_platform(w.name)
            if p in by_platform:
                sys.exit(f"build_addon: two wheels for {p}: {by_platform[p]} and {w.name}")
            by_platform[p] = w.name
        platforms = sorted(by_platform)
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
    if args.split_platforms and not platforms:
        sys.exit("build_addon: --split-platforms needs wheels with their platforms (--wheel or --compat)")
    output = args.output
    if args.split_platforms and output == ap.get_default("output"):
        output = ROOT / "dist" / "extensions"
    bundled = bundle_wheels(wheels)
    zips = build_zip(stage([b.name for b in bundled], platforms), output.resolve(), args.split_platforms)
    names = ", ".join(b.name for b in bundled)
    for z in zips:
        print(f"build_addon: {z} ({z.stat().st_size / 1e6:.1f} MB, from wheels {names})")


if __name__ == "__main__":
    main()
