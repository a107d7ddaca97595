# Tailor: the two commands of the README are `make demo` and `make test`.
# Everything installs into the project-local virtual environment .venv (see .ci/bootstrap).

VENV   := .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.tailor-built
SOURCES := $(shell find native -name '*.rs' -o -name '*.toml' -o -name '*.py' -o -name '*.pyi' -o -name '*.wgsl') Cargo.toml pyproject.toml

.PHONY: demo test test-rust test-python bench bench-peers setup develop clean

## Set everything up and run the main job (headless drape of a sewn garment).
demo: develop
	$(PY) -m tailor demo --out out/demo

## Run every test: the crates' own tests, then pytest against the built module.
test: setup develop test-rust test-python

test-rust:
	cargo test --workspace --release
	# The wgpu backend (feature gpu) on whatever Vulkan adapter exists (lavapipe in CI); its
	# tests print SKIP and pass when there is none.
	cargo test -p tailor-core --release --features gpu --test gpu_solver
	cargo test -p tailor-core --release --features gpu --lib gpu::

test-python: develop
	$(PY) -m pytest -q tests

## Benchmarks (print figures; not part of the tests).
bench: develop
	cargo bench -p tailor-core --bench solver

## Tailor against Blender's Cloth and Newton on the same scenes (docs/benchmarks.md, "Against peers").
bench-peers: develop
	bash bench/peers/setup.sh
	$(PY) bench/peers/run.py

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
	rm -rf $(VENV) target out
