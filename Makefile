# Tailor: the two commands of the README are `make demo` and `make test`.
# Everything installs into the project-local virtual environment .venv (see .ci/bootstrap).

VENV   := .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.tailor-built
SOURCES := $(shell find native -name '*.rs' -o -name '*.toml' -o -name '*.py' -o -name '*.pyi' -o -name '*.wgsl') Cargo.toml pyproject.toml

.PHONY: demo test test-rust test-python bench bench-error stress setup develop clean

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

## Run time against error and the quality presets: out/bench/*.json, docs/img/*.png, docs/accuracy.md.
bench-error: setup
	cargo run --release -p tailor-core --example accuracy -- --out out/bench --sizes 1000,10000 --frames 45
	$(PY) bench/plot_accuracy.py out/bench

## The whole numerical stress suite (docs/stability.md); `make test` runs a quick subset.
stress:
	cargo run --release -p tailor-core --example stress -- --out docs/stability.md

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
