# Tailor: the two commands of the README are `make demo` and `make test`.
# Everything installs into the project-local virtual environment .venv (see .ci/bootstrap).

VENV   := .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.tailor-built
SOURCES := $(shell find native -name '*.rs' -o -name '*.toml' -o -name '*.py' -o -name '*.pyi' -o -name '*.wgsl') Cargo.toml pyproject.toml

ADDON_ZIP := dist/tailor_addon.zip
ADDON_SOURCES := $(shell find addon -name '*.py' -not -path '*/_vendor/*' -o -name '*.toml')

.PHONY: bench-fabric bench-batch bench-gpu device-bin fuzz drape-suite demo test test-rust test-python test-addon test-gui addon addon-studio bench setup develop clean samples-character bench-peers bench-addon diagnose-bake bench-error stress samples bench-addon-shirt profile-live

## Set everything up and run the main job (headless drape of a sewn garment).
demo: develop
	$(PY) demo/run.py --out out/demo

## Run every test: the crates' own tests, then pytest against the built module.
test: setup develop test-rust test-python

test-rust:
	cargo test --workspace --release
	# The wgpu backend (feature gpu) on lavapipe (installed by setup) or a real adapter:
	# TAILOR_REQUIRE_GPU=1 makes a GPU test that finds no adapter fail instead of skipping.
	TAILOR_REQUIRE_GPU=1 cargo test -p tailor-core --release --features gpu --test gpu_solver
	TAILOR_REQUIRE_GPU=1 cargo test -p tailor-core --release --features gpu --lib gpu::

test-python: develop
	TAILOR_REQUIRE_GPU=1 $(PY) -m pytest -q tests --ignore=tests/addon --ignore=tests/gui
	$(MAKE) test-addon
	$(MAKE) test-gui

## The Blender add-on's tests: install the built zip into a throw-away Blender user directory
## (bpy wheel, headless) in a process of its own, so it uses the wheel bundled in the zip.
test-addon: addon
	$(PY) -m pytest -q --confcutdir=tests/addon tests/addon

## The interactive tools in a real Blender window: Debian's blender under xvfb-run with simulated
## mouse events (tests/gui/driver.py); screenshots go to out/gui/. Skipped without blender/xvfb-run.
test-gui: addon
	$(PY) -m pytest -q tests/gui

## The installable Blender extension: dist/tailor_addon.zip with the tailor wheel bundled.
addon: $(ADDON_ZIP)

$(ADDON_ZIP): $(STAMP) $(ADDON_SOURCES)
	$(PY) addon/build_addon.py -o $@

## The extension for studio Linux: wheels against glibc 2.28 (Rocky/Alma Linux 8) for x86-64
## and arm64, built with maturin --zig (zig from PyPI's ziglang), each checked for newer glibc
## symbols: dist/tailor_addon_studio.zip.
addon-studio: $(STAMP)
	$(PY) -m pip install --quiet ziglang auditwheel
	rustup target add aarch64-unknown-linux-gnu
	$(PY) addon/build_addon.py --compat manylinux_2_28 --arch x86_64,aarch64 -o dist/tailor_addon_studio.zip

## Assembly on patterns nobody tuned: random GarmentCode designs (../shared/tools/garmentcode)
## imported and simulated with default settings, judged by `tailor simulate`'s own checks;
## prints the share that succeed, pictures of the failures in out/drape-suite/failures
## (docs/benchmarks.md, "Drape suite"). DRAPE_ARGS, e.g. --seed 18 --count 30.
drape-suite: develop
	$(PY) bench/drape_suite/run.py $(DRAPE_ARGS)

## The mutation fuzzer over every reader and the API (tests/fuzz/fuzz.py; docs/hardening.md), longer
## than the seeded run in `make test`: FUZZ_SEED, FUZZ_CASES. Failing cases are kept in
## tests/fuzz/crashes/, which `make test` replays.
FUZZ_SEED  ?= 1
FUZZ_CASES ?= 50000
fuzz: develop
	$(PY) tests/fuzz/fuzz.py --seed $(FUZZ_SEED) --cases $(FUZZ_CASES)

## Benchmarks (print figures; not part of the tests).
bench: develop
	cargo bench -p tailor-core --bench solver

## tailor batch against the same jobs run one after the other with tailor simulate: jobs per hour and
## the overhead per job (docs/batch.md, "Throughput"). BATCH_ARGS, e.g. --repeat 8 --frames 60.
bench-batch: develop
	$(PY) bench/batch/run.py $(BATCH_ARGS)

## Add-on level (bpy wheel): the sample garments on the walking character, Tailor's Live fps and
## Bake s/frame against Blender's Cloth with sewing springs, with the quality of both
## (docs/benchmarks.md, "Add-on: Simulate"). BENCH_ARGS, e.g. --garments tshirt,skirt,trousers,layered.
bench-addon: addon
	$(PY) tests/addon/bench_garments.py $(BENCH_ARGS)

## Where a Live frame of the add-on goes: the benchmark's Live run, each part of a frame timed
## (docs/benchmarks.md, "Where a Live frame goes"). PROFILE_ARGS, e.g. --profile, --modal 0.005.
profile-live: addon
	$(PY) tests/addon/profile_live.py $(PROFILE_ARGS)

## Add-on level: Live fps and Bake s/frame of the imported GarmentCode shirt, proxy against body collider.
bench-addon-shirt: addon
	$(PY) tests/addon/bench_simulate.py

## When and where the Simulate test scene's bake loses quality: one line per preroll, transition
## and recorded frame (seam gap, penetration into the collider and the body, strain, where).
diagnose-bake: addon
	$(PY) tests/addon/diagnose_bake.py

## Regenerate sample_blends/character.blend and .glb (rig, skin, walk and run) from
## sample_blends/sources, with contact sheets in out/character and the docs' previews.
## Needs the bpy wheel in .venv: .venv/bin/pip install "bpy==4.5.*".
samples-character: setup
	$(PY) sample_blends/build/character.py --render out/character --docs-img docs/img

## Tailor against Blender's Cloth and Newton on the same scenes (docs/benchmarks.md, "Against peers").
bench-peers: develop
	bash bench/peers/setup.sh
	$(PY) bench/peers/run.py

## Run time against error and the quality presets: out/bench/*.json, docs/img/*.png, docs/accuracy.md.
## The GPU engine against the CPU (10k/100k/1M with body and self collision, the four samples on
## the walk); a table into out/bench-gpu/bench-gpu.md. For a machine with a GPU (docs/gpu.md).
bench-gpu: develop
	$(PY) bench/gpu/run.py --out out/bench-gpu

## The binaries and loaders bench/gpu/on_device.sh needs on a lent GPU machine (docs/gpu.md).
device-bin: setup
	bash bench/gpu/prepare_device.sh

## The cantilever and Cusick drape tests simulated (issue 28): tables to stdout, a few minutes.
bench-fabric: develop
	$(PY) bench/fabric/standard_tests.py

bench-error: setup
	cargo run --release -p tailor-core --example accuracy -- --out out/bench --sizes 1000,10000 --frames 45
	$(PY) bench/plot_accuracy.py out/bench

## The whole numerical stress suite (docs/stability.md); `make test` runs a quick subset.
stress:
	cargo run --release -p tailor-core --example stress -- --out docs/stability.md

## Regenerate the sample garments (sample_blends/{tshirt,skirt,trousers,layered}.blend and their
## garment files) with the add-on's operators, then check that each assembles on the character.
samples: develop
	$(PY) sample_blends/build/garments.py
	$(PY) sample_blends/build/check_garments.py

setup: $(VENV)/.tailor-setup

$(VENV)/.tailor-setup: .ci/bootstrap
	bash .ci/bootstrap
	touch $@

develop: $(STAMP)

$(STAMP): $(VENV)/.tailor-setup $(SOURCES)
	VIRTUAL_ENV=$(abspath $(VENV)) PATH=$(abspath $(VENV))/bin:$$PATH \
		$(VENV)/bin/maturin develop --release --quiet
	touch $@

clean:
	rm -rf $(VENV) target out build dist addon/tailor_addon/wheels addon/tailor_addon/_vendor
