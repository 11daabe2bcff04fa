# make generate [SPEC=specs/x.toml]   derive and emit generated/<name>/ (default: the gimbal)
# make test                           set up .venv and run every derivation, accuracy, physics and command test (before a commit)
# make test-all                       everything CI runs: make test, and the installed wheel, QEMU, the static analysers, the
#                                     fuzz lanes, the documentation site in a browser, TeX, and on every example and random spec
#                                     the checks make test runs on a few (the extended tier, tests/conftest.py)
# make test-fast                      the unit layer only: the stages, printers, pipeline and architecture, no compiler (< 1 min)
# make dist                           the source archive and the wheel into dist/, checked by twine (a build-only venv: seconds)
# make test-install                   the package as users install it: sdist and wheel built, installed into a fresh venv,
#                                     the tour run from an empty folder (part of make test-all; needs the package index)
# make plot                           the tables and charts of docs/benchmarks.md (from bench/results/*.csv), the frames figure,
#                                     the gimbal's quadrature over an ODE solution, the Furuta LQR loop, the flip map,
#                                     Kapitza's stability chart, the double pendulum's nonlinear normal modes, the tutorial's PDF page,
#                                     identify's two validations (docs/img/)
# make animations                     the README's animations: the gimbal and a chaotic 3-link chain (docs/)
# make gallery                        the pictures of docs/gallery.md, each drawn by the commands its card shows (docs/img/gallery/)
# make docs                           the documentation site from docs/ into site/ (MkDocs, warnings are errors; works from file://, offline)
# make fuzz                           the commands fuzzed with fresh random inputs, then fresh chains of the geometry users write
#                                     through every emitted target, each for FUZZ_SECONDS (default 600)
# make bench                          integrators against scipy: work-precision, 1e5-period drift, rhs cost; ensembles against
#                                     scipy and MuJoCo's rollout on 1 and 2 cores and a local Dask cluster; the variational
#                                     equations against scipy (bench/results/)
# make bench-speed                    generated C against Pinocchio, CasADi, MuJoCo; derivatives against Pinocchio, CasADi, differences;
#                                     the imported UR5 and Panda against Pinocchio on their URDF; every emitted function of this
#                                     release against the previous release's, n = 2...128 (bench/results/)
SHELL := /bin/bash
PY ?= python3
VENV := .venv
VPY := $(VENV)/bin/python
SPEC ?= specs/gimbal.toml
EXAMPLES := $(wildcard specs/*.toml)
export PYTHONHASHSEED := 0

.PHONY: all setup generate generate-all test test-all test-fast test-install docs fuzz pdf plot animations clean bench bench-setup bench-speed dist gallery

all: generate

$(VENV)/.installed: pyproject.toml gyrochain/__init__.py  # (the version: the metadata pip installed says it)
	$(PY) -m venv $(VENV)
	$(VPY) -m pip install -q --upgrade pip
	$(VPY) -m pip install -q -e '.[test,sweep,view,browser,docs,robots,casadi]'
	touch $@

setup: $(VENV)/.installed

generate: setup
	$(VPY) -m gyrochain generate $(SPEC)

generate-all: setup
	@for s in $(EXAMPLES); do $(VPY) -m gyrochain generate -q $$s || exit 1; done

# the suite on JOBS processes (pytest-xdist; a file stays on one worker, so its models are built once)
JOBS ?= 2
test: setup
	$(VPY) -m pytest -q -n $(JOBS) --dist loadfile --durations=25 -m "not extended"

test-all: setup
	$(VPY) -m pytest -q -n $(JOBS) --dist loadfile --durations=25

test-fast: setup
	$(VPY) -m pytest -q -n $(JOBS) tests/unit

test-install: setup
	$(VPY) -m pytest -q tests/tools/test_install.py

# the source archive and the wheel (built from it), as a release ships them, checked as the index checks them
# the source archive and the wheel, built in a venv of their own with build and twine alone (not
# the test extras of .venv): seconds, and nothing but the build backend downloaded
DIST_VENV := .venv-dist
$(DIST_VENV)/.installed:
	$(PY) -m venv $(DIST_VENV)
	$(DIST_VENV)/bin/python -m pip install -q --upgrade pip build twine
	touch $@

dist: $(DIST_VENV)/.installed
	rm -rf dist
	$(DIST_VENV)/bin/python -m build -o dist .
	$(DIST_VENV)/bin/python -m twine check --strict dist/*

docs: setup
	NO_MKDOCS_2_WARNING=1 $(VPY) -m mkdocs build --strict -q -d site
	@echo "site/index.html: open it in a browser (from the file, offline: navigation, search and formulas work)"

FUZZ_SECONDS ?= 600
fuzz: setup
	FUZZ_SECONDS=$(FUZZ_SECONDS) $(VPY) -m pytest -q -s tests/tools/test_fuzz.py tests/models/test_geometry.py -k fuzz_for_a_while

$(VENV)/.plot-installed: $(VENV)/.installed pyproject.toml
	$(VPY) -m pip install -q -e '.[test,plot,sweep,view,rollout,casadi]'
	touch $@

# each chart also drawn for a phone (X.phone.png beside X.png: its panels in a column, its text legible at 390 px)
PHONE = $(VPY) examples/phone_figures.py

plot: $(VENV)/.plot-installed
	$(VPY) -m gyrochain generate -q specs/gimbal.toml >/dev/null
	$(PHONE) examples/frames_figure.py docs/img/frames.png
	$(PHONE) examples/plot_gimbal.py docs/img/gimbal_quadrature.png
	$(VPY) -m gyrochain generate -q specs/furuta.toml >/dev/null
	$(PHONE) examples/furuta_lqr.py docs/img/furuta_lqr.png
	$(PHONE) examples/furuta_swing_up.py docs/img/furuta_swing_up.png
	rm -rf build/flip_map.zarr
	$(VPY) -m gyrochain sweep specs/double_pendulum.toml --vary link1=-3.14:3.14:300 --vary link2=-3.14:3.14:300 \
		--t1 10 --measure flip_time --device auto -q -o build/flip_map.zarr
	$(PHONE) -m gyrochain plot build/flip_map.zarr --log -o docs/img/double_pendulum_flip.png
	$(VPY) -m gyrochain generate -q specs/kapitza.toml >/dev/null
	$(PHONE) examples/kapitza_chart.py docs/img/kapitza_chart.png
	$(VPY) -m gyrochain generate -q specs/double_pendulum_point.toml >/dev/null
	$(PHONE) examples/nnm_periods.py docs/img/nnm_periods.png
	$(VPY) -m gyrochain continue specs/turntable.toml --vary Omega=2:12 -o build/turntable_branches.csv --force >/dev/null
	$(PHONE) -m gyrochain plot build/turntable_branches.csv -o docs/img/continuation_turntable.png
	$(VPY) -m gyrochain continue specs/kapitza.toml --vary a=0.001:0.15 --vary w=100:1000 --param w=300 \
		-o build/kapitza_branches.csv --force >/dev/null
	$(PHONE) -m gyrochain plot build/kapitza_branches.csv -o docs/img/continuation_kapitza.png
	$(VPY) -m gyrochain continue specs/double_pendulum_point.toml --vary energy=0.01:30 -o build/nnm_branches.csv \
		--force >/dev/null
	$(PHONE) -m gyrochain plot build/nnm_branches.csv -o docs/img/continuation_nnm.png
	$(VPY) bench/report.py
	$(VPY) examples/tutorial_page.py docs/img/tutorial_page.png
	$(VPY) examples/identify_pictures.py

gallery: setup
	$(VPY) examples/gallery.py

animations: setup
	$(VPY) -m gyrochain animate specs/gimbal.toml --t1 8 --fps 20 --size 340x340 -o docs/img/gimbal.gif
	$(VPY) -m gyrochain animate specs/spatial3.toml --phi=-2,-0.75,-1.1 --phidot 0,0,0 --t1 8 --fps 20 --size 340x340 \
		-o docs/img/spatial3_chaos.gif
	$(VPY) -m gyrochain animate specs/cable64.toml --t1 4 --fps 20 --size 340x340 -o docs/img/cable64.gif

$(VENV)/.bench-installed: $(VENV)/.installed pyproject.toml
	$(VPY) -m pip install -q -e '.[test,bench]'
	@# Eigen headers for the Pinocchio peer (the pin wheel ships Pinocchio and Boost, not Eigen)
	@test -d /usr/include/eigen3 || { command -v apt-get >/dev/null && [ "$$(id -u)" = 0 ] && \
		DEBIAN_FRONTEND=noninteractive apt-get install -y -q libeigen3-dev >/dev/null; } || \
		echo "no /usr/include/eigen3: the Pinocchio peer will be skipped (apt-get install libeigen3-dev)"
	touch $@

bench-setup: $(VENV)/.bench-installed

bench: $(VENV)/.plot-installed
	$(VPY) bench/integrators.py
	$(VPY) bench/ensemble.py
	$(VPY) bench/lanes.py
	$(VPY) bench/variational.py
	$(VPY) bench/report.py

bench-speed: bench-setup
	$(VPY) bench/speed.py --instructions
	$(VPY) bench/derivatives.py
	$(VPY) bench/robots.py
	$(VPY) bench/releases.py --instructions
	$(VPY) bench/casadi_ocp.py

# the LaTeX typeset by LuaLaTeX (Debian: texlive-luatex, texlive-latex-recommended, fonts-dejavu-core), two passes
# for the tables' widths; PAPER=letter for US letter
PAPER ?= a4
pdf: setup
	@command -v lualatex >/dev/null || { echo "make pdf needs lualatex: apt-get install texlive-luatex texlive-latex-recommended fonts-dejavu-core"; exit 1; }
	$(VPY) -m gyrochain generate -q --no-build --paper $(PAPER) $(SPEC) >/dev/null
	@name=$$($(VPY) -c "from gyrochain.spec import load_spec; print(load_spec('$(SPEC)').name)"); \
	cd generated/$$name && lualatex -interaction=nonstopmode -halt-on-error $$name.tex >/dev/null \
		&& lualatex -interaction=nonstopmode -halt-on-error $$name.tex >/dev/null && echo "generated/$$name/$$name.pdf"

clean:
	rm -rf $(VENV) $(DIST_VENV) .pytest_cache build dist site *.egg-info
