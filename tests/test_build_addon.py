"""The extension build (`addon/build_addon.py`): which Blender platform a wheel is for, and the
release's per-platform zips (`--wheel ... --split-platforms`), built by Blender's own
extension builder from the `bpy` wheel. The wheels here are stand-ins (a zip with a wheel's
name): the builder files wheels by their names' platform tags, which is what is tested; real
wheels for Windows and macOS come from the release workflow's runners, not from here."""

import importlib.util
import shutil
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
spec = importlib.util.spec_from_file_location("build_addon", ROOT / "addon" / "build_addon.py")
build_addon = importlib.util.module_from_spec(spec)
spec.loader.exec_module(build_addon)


@pytest.mark.parametrize("name, platform", [
    ("tailor-0.1.0-cp311-abi3-manylinux_2_28_x86_64.whl", "linux-x64"),
    ("tailor-0.1.0-cp311-abi3-manylinux_2_17_x86_64.manylinux2014_x86_64.whl", "linux-x64"),
    ("tailor-0.1.0-cp311-abi3-manylinux_2_28_aarch64.whl", "linux-arm64"),
    ("tailor-0.1.0-cp311-abi3-win_amd64.whl", "windows-x64"),
    ("tailor-0.1.0-cp311-abi3-win_arm64.whl", "windows-arm64"),
    ("tailor-0.1.0-cp311-abi3-macosx_10_12_x86_64.whl", "macos-x64"),
    ("tailor-0.1.0-cp311-abi3-macosx_11_0_arm64.whl", "macos-arm64"),
])
def test_a_wheels_platform_tag_names_blenders_platform(name, platform):
    assert build_addon.blender_platform(name) == platform


@pytest.mark.parametrize("name, says", [
    ("tailor-0.1.0-cp311-abi3-macosx_10_12_universal2.whl", "no platform Blender knows"),
    ("tailor-0.1.0-cp311-abi3-win_amd64.macosx_11_0_arm64.whl", "several platforms"),
    ("tailor-0.1.0-cp311-abi3-any.whl", "no platform Blender knows"),
    ("tailor.zip", "not a wheel file name"),
])
def test_a_wheel_for_no_one_platform_is_refused_by_name(name, says):
    with pytest.raises(SystemExit, match=says):
        build_addon.blender_platform(name)


def fake_wheel(folder: Path, tag: str) -> Path:
    w = folder / f"tailor-0.1.0-cp311-abi3-{tag}.whl"
    with zipfile.ZipFile(w, "w") as z:
        z.writestr("tailor-0.1.0.dist-info/WHEEL", f"Wheel-Version: 1.0\nTag: cp311-abi3-{tag}\n")
    return w


def test_split_platforms_gives_each_platform_a_zip_with_its_wheel_alone(tmp_path):
    before = sorted(build_addon.WHEELS.glob("*.whl"))
    wheels = [fake_wheel(tmp_path, t) for t in ("manylinux_2_28_x86_64", "win_amd64", "macosx_11_0_arm64")]
    addon = tmp_path / "src" / "tailor_addon"
    shutil.copytree(build_addon.ADDON, addon, ignore=shutil.ignore_patterns("__pycache__", "*.pyc", "_vendor", "wheels"))
    bundled = build_addon.bundle_wheels(wheels, into=addon / "wheels")
    platforms = sorted(build_addon.blender_platform(w.name) for w in wheels)
    staged = build_addon.stage([b.name for b in bundled], platforms, addon=addon, stage_dir=tmp_path / "stage")
    zips = build_addon.build_zip(staged, tmp_path / "ext", split=True)
    assert [z.name.rsplit("-", 1)[1] for z in zips] == ["linux_x64.zip", "macos_arm64.zip", "windows_x64.zip"]
    for z, tag in zip(zips, ("manylinux_2_28_x86_64", "macosx_11_0_arm64", "win_amd64")):
        with zipfile.ZipFile(z) as f:
            inside = [n for n in f.namelist() if n.endswith(".whl")]
            assert inside == [f"wheels/tailor-0.1.0-cp311-abi3-{tag}.whl"], (z.name, inside)
            assert "__init__.py" in f.namelist()
    # The add-on's own wheels (the legacy add-on path loads them) are untouched.
    assert sorted(build_addon.WHEELS.glob("*.whl")) == before


def test_the_release_workflow_builds_a_wheel_per_platform_and_splits_them():
    # The workflow itself runs only on hosted runners (untested here); this checks what it
    # promises: every target's wheel names a distinct Blender platform, and the extension job
    # splits them with this script.
    import yaml  # PyYAML: .ci/bootstrap installs it
    flow = yaml.safe_load((ROOT / ".github" / "workflows" / "release.yml").read_text())
    matrix = flow["jobs"]["wheels"]["strategy"]["matrix"]["include"]
    tag_of_target = {
        "x86_64-unknown-linux-gnu": "manylinux_2_28_x86_64",
        "aarch64-unknown-linux-gnu": "manylinux_2_28_aarch64",
        "x86_64-pc-windows-msvc": "win_amd64",
        "aarch64-apple-darwin": "macosx_11_0_arm64",
        "x86_64-apple-darwin": "macosx_10_12_x86_64",
    }
    platforms = [build_addon.blender_platform(f"tailor-0.1.0-cp311-abi3-{tag_of_target[m['target']]}.whl")
                 for m in matrix]
    assert sorted(platforms) == ["linux-arm64", "linux-x64", "macos-arm64", "macos-x64", "windows-x64"]
    steps = "\n".join(s.get("run", "") for s in flow["jobs"]["extension"]["steps"])
    assert "addon/build_addon.py" in steps and "--split-platforms" in steps and "--wheel" in steps


def wheel_of_the_built_module(tmp_path: Path) -> Path:
    """A wheel holding the `_tailor` library `maturin develop` built here (the real ELF file
    auditwheel reads), tagged for no particular glibc (`linux_x86_64`, as maturin's own are
    before a manylinux check)."""
    import platform

    so = ROOT / "native" / "python" / "tailor" / "_tailor.abi3.so"
    assert so.is_file(), f"{so} is missing: make develop"
    arch = platform.machine()
    wheel = tmp_path / f"tailor-0.1.0-cp311-abi3-linux_{arch}.whl"
    info = "tailor-0.1.0.dist-info"
    files = {
        "tailor/_tailor.abi3.so": so.read_bytes(),
        f"{info}/METADATA": b"Metadata-Version: 2.1\nName: tailor\nVersion: 0.1.0\n",
        f"{info}/WHEEL": f"Wheel-Version: 1.0\nGenerator: test\nRoot-Is-Purelib: false\n"
                         f"Tag: cp311-abi3-linux_{arch}\n".encode(),
    }
    record = "".join(f"{n},,\n" for n in files) + f"{info}/RECORD,,\n"
    with zipfile.ZipFile(wheel, "w") as z:
        for name, data in files.items():
            z.writestr(name, data)
        z.writestr(f"{info}/RECORD", record)
    return wheel


def test_auditwheel_reads_the_platform_tag_a_wheel_is_consistent_with():
    report = ('\ntailor-0.1.0-cp311-abi3-linux_x86_64.whl is consistent with\nthe following platform tag: '
              '"manylinux_2_28_aarch64".\n\nThe wheel references external versioned symbols')
    assert build_addon.auditwheel_tag(report) == ((2, 28), "aarch64")
    assert build_addon.auditwheel_tag("tailor.whl is consistent with the following platform tag: \"linux_x86_64\"") is None


def test_auditwheel_passes_a_wheel_for_its_glibc_and_refuses_an_older_promise(tmp_path, capsys):
    """The check `make addon-studio` runs on each wheel, on the module built here: auditwheel
    finds it consistent with this machine's glibc tag, which passes, and an older promise
    (manylinux_2_17: what this build does not keep) stops the build naming both."""
    import platform
    import re
    import subprocess
    import sys

    wheel = wheel_of_the_built_module(tmp_path)
    arch = platform.machine()
    shown = subprocess.run([sys.executable, "-m", "auditwheel", "show", str(wheel)], capture_output=True, text=True)
    assert shown.returncode == 0, shown.stderr
    (major, minor), found_arch = build_addon.auditwheel_tag(shown.stdout)
    assert found_arch == arch and (major, minor) >= (2, 17)
    build_addon.check_auditwheel(wheel, f"manylinux_{major}_{minor}", arch)
    assert f"consistent with manylinux_{major}_{minor}_{arch}" in capsys.readouterr().out
    with pytest.raises(SystemExit, match=re.escape(f"manylinux_{major}_{minor}_{arch}, not manylinux_2_17_{arch}")):
        build_addon.check_auditwheel(wheel, "manylinux_2_17", arch)
