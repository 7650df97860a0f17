# The two set-up commands of the README:
#   make run   installs what is missing, builds in Release, runs the default scene and plots it
#   make test  installs what is missing, builds, runs the whole test suite (Release, then ASan+UBSan,
#              then the threaded tests under ThreadSanitizer)
#   make package  the Debian packages vascsim and vascsim-dev (CPack; docs/api.md)
BUILD_DIR ?= build
ASAN_DIR  ?= build-asan
TSAN_DIR  ?= build-tsan
PACKAGE_DIR ?= build-package
SCENE     ?= scenes/vein-indent.json
OUT       ?= out/vein-indent
PYTHON    ?= /usr/bin/python3
JOBS      ?= $(shell nproc)
# The libraries are compiled as unity batches of 8 sources (each Eigen/JSON header parsed and each template
# instantiated once per batch, not once per file: about half the compile time of a fresh build, which is most of
# `make test`). UNITY=OFF compiles file by file, quicker for small incremental rebuilds while developing.
UNITY     ?= ON
CMAKE_UNITY = -DCMAKE_UNITY_BUILD=$(UNITY) -DCMAKE_UNITY_BUILD_BATCH_SIZE=8

.PHONY: deps build run test test-release test-sanitize test-threads package check-deb bench bench-realtime compare-models xpbd-convergence \
  cantilever-table vessels vessel-aorta-vmtk mls-validation force-displacement catheter-aorta experiments fig10 timing \
  screenshots view-bench fuzz soak format clean

deps:
	@scripts/install-deps.sh

build: deps
	cmake -S . -B $(BUILD_DIR) -G Ninja -DCMAKE_BUILD_TYPE=Release -DVASCSIM_WERROR=ON $(CMAKE_UNITY)
	cmake --build $(BUILD_DIR) -j $(JOBS)

run: build
	$(BUILD_DIR)/vascsim run $(SCENE) --out $(OUT)
	$(PYTHON) scripts/plot_probes.py $(OUT)

test: test-release test-sanitize test-threads

test-release: build
	ctest --test-dir $(BUILD_DIR) --output-on-failure -j $(JOBS)

# The unit tests again under AddressSanitizer + UndefinedBehaviorSanitizer (-O1, asserts on), except those
# that measure against the wall clock (label "wallclock": the instrumented model cannot keep up). Without the
# viewer: its tests (label "render") run in the Release build only, and this also checks that the library
# builds without any GL package, and without the Python module (label "python": a Python process would have to
# preload the sanitizer runtime) and the install test (label "install"), which run in the Release stage. -g1
# (line tables: the sanitizers' reports name file and line) instead of -g compiles about a quarter faster.
# Both sanitizer stages build with clang (Debian's clang-14, the sanitizers' home; OpenMP through its libomp):
# measured against g++ 12 with the same checks, the ASan+UBSan library and tests compiled in 0.8x the time and
# the tests ran in half the time, and g++ reports false warnings inside libstdc++ at -O1 with instrumentation. So
# a second compiler checks the code too; warnings are not errors here, the Release build (g++, -Wall -Wextra
# -Wpedantic -Werror) is the warning gate.
SANITIZER_CXX ?= clang++-14
SANITIZER_FLAGS = -O1 -g1
test-sanitize: deps
	cmake -S . -B $(ASAN_DIR) -G Ninja -DCMAKE_CXX_COMPILER=$(SANITIZER_CXX) -DCMAKE_BUILD_TYPE=Debug \
	  -DCMAKE_CXX_FLAGS_DEBUG="$(SANITIZER_FLAGS)" $(CMAKE_UNITY) \
	  -DVASCSIM_SANITIZE=address,undefined -DVASCSIM_BUILD_BENCH=OFF -DVASCSIM_BUILD_VIEWER=OFF -DVASCSIM_WERROR=OFF \
	  -DVASCSIM_BUILD_PYTHON=OFF
	cmake --build $(ASAN_DIR) -j $(JOBS)
	ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
	  ctest --test-dir $(ASAN_DIR) --output-on-failure -j $(JOBS) -L unit -LE wallclock

# The tests that run threads (haptic loop, hand-offs, mouse input, the realtime haptic session, the viewer's
# live session: UI commands, simulation thread, haptic thread and a frame reader) under ThreadSanitizer. Only
# these, and with OMP_NUM_THREADS=1: the OpenMP runtime (libomp) is not instrumented, so TSan would report its
# internals; the threads under test are the haptic thread and the simulation thread, which are std::threads.
# -O1 -g1 compiles about a third faster than -O2 -g. The executable vascsim_threaded_tests holds only the test
# files of these suites (tests/CMakeLists.txt lists them: a suite added here needs its file there).
THREADED_TESTS ?= LatestValue*:FrameExchange*:HapticLoop*:VirtualCoupling*:ForceOutput*:MouseMapping*:HapticSession.Realtime*:LiveSession.Realtime*
test-threads: deps
	cmake -S . -B $(TSAN_DIR) -G Ninja -DCMAKE_CXX_COMPILER=$(SANITIZER_CXX) -DCMAKE_BUILD_TYPE=RelWithDebInfo \
	  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="$(SANITIZER_FLAGS) -DNDEBUG" \
	  $(CMAKE_UNITY) \
	  -DVASCSIM_SANITIZE=thread \
	  -DVASCSIM_BUILD_BENCH=OFF -DVASCSIM_BUILD_VIEWER=OFF -DVASCSIM_WERROR=OFF -DVASCSIM_BUILD_PYTHON=OFF
	cmake --build $(TSAN_DIR) -j $(JOBS) --target vascsim_threaded_tests
	OMP_NUM_THREADS=1 TSAN_OPTIONS=halt_on_error=1:second_deadlock_stack=1 $(TSAN_DIR)/tests/vascsim_threaded_tests \
	  --gtest_filter='$(THREADED_TESTS)'

# The Debian packages (cmake/VascsimPackage.cmake): a Release build of its own installed to /usr, without tests
# and benchmarks; vascsim_VERSION_ARCH.deb (library, command, Python module, scenes, data, scripts) and
# vascsim-dev_VERSION_ARCH.deb (headers, CMake package) in $(PACKAGE_DIR).
package: deps
	cmake -S . -B $(PACKAGE_DIR) -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_INSTALL_PREFIX=/usr $(CMAKE_UNITY) \
	  -DVASCSIM_BUILD_TESTS=OFF -DVASCSIM_BUILD_BENCH=OFF -DVASCSIM_WERROR=ON
	cmake --build $(PACKAGE_DIR) -j $(JOBS)
	cd $(PACKAGE_DIR) && cpack -G DEB
	@ls -l $(PACKAGE_DIR)/*.deb

# Installs the packages on a fresh Debian 12 in a chroot (debootstrap; root, network to deb.debian.org; minutes)
# and runs the installed vascsim, Python module and examples/embed there (docs/api.md, "Debian package").
check-deb: package
	scripts/check-deb-in-chroot.sh $(PACKAGE_DIR)

bench: build
	$(BUILD_DIR)/bench/vascsim_bench --benchmark_repetitions=5 --benchmark_report_aggregates_only=true

# docs/performance.md's real-time benchmark: xpbd on the vein at ~1k-30k nodes, 1 and 2 threads (minutes;
# run it on an otherwise idle machine).
bench-realtime: build
	$(BUILD_DIR)/vascsim bench scenes/vein-indent.json --out out/bench/realtime.json --out out/bench/realtime.csv

# vein-indent with quasi_static, explicit, xpbd and paper_literal on one force-displacement figure
# (docs/validation.md; about 25 minutes on 2 cores).
# The paper's three vessels, each indented on its outer wall (quasi-static, about 5 min each on 2 cores),
# with a shaded picture of the last frame: out/<scene>/surface.png.
VESSELS ?= hand-dorsal-vein aorta-bent retinal-artery-twice-bent
vessels: build
	@for v in $(VESSELS); do \
	  $(BUILD_DIR)/vascsim run scenes/$$v.json --out out/$$v && \
	  $(PYTHON) scripts/render_surface.py out/$$v/vtk/surface.pvd --color displacement --out out/$$v/surface.png \
	  || exit 1; done

# The imported VMTK aorta (88k nodes; quasi-static, 6 load steps in about 2-3 min on 2 cores, 6 GB of memory).
vessel-aorta-vmtk: build
	$(BUILD_DIR)/vascsim run scenes/aorta-vmtk.json --out out/aorta-vmtk
	$(PYTHON) scripts/render_surface.py out/aorta-vmtk/vtk/surface.pvd --color displacement --outer-only \
	  --elev 35 --azim -70 --out out/aorta-vmtk/surface.png

# docs/validation.md's T11/T15 table of the MLS map on every vessel (seconds; no solve).
mls-validation: build
	$(BUILD_DIR)/vascsim validate mls scenes/hand-dorsal-vein.json scenes/aorta-bent.json \
	  scenes/retinal-artery-twice-bent.json scenes/aorta-vmtk.json --out out/mls-validation

# The paper's Fig. 10: a 6 Fr catheter tip presses the hand dorsal vein (quasi-static, frictionless contact;
# about 10-20 min on 2 cores). force_displacement.csv and .png in out/hand-dorsal-vein-catheter-force-displacement.
force-displacement: build
	$(BUILD_DIR)/vascsim experiment force-displacement scenes/hand-dorsal-vein-catheter.json

# The interventional scene: a scripted catheter advances in the bent aorta and presses the outer wall of
# the bend through the 1 kHz haptic loop (lockstep); force history, session recording, surface series.
catheter-aorta: build
	$(BUILD_DIR)/vascsim run scenes/aorta-bent-catheter.json --out out/aorta-bent-catheter
	$(PYTHON) scripts/render_surface.py out/aorta-bent-catheter/vtk/surface.pvd --color displacement \
	  --out out/aorta-bent-catheter/surface.png

# The README's pictures by the viewer (headless through EGL: no display needed), lit and fluoroscopic, into
# docs/images/view-*.png: the three paper vessels with their indenter pushed in full (quasi_static: one
# equilibrium at full load per scene, 1-2 min each on 2 cores), the imported VMTK aorta at its full resolution
# (88k nodes: its wall's 3 node layers fix the lattice at 0.5 mm, so a coarser node_spacing_m changes nothing;
# one equilibrium at full load, about 2.5 min here), and the catheter scene at 1.3 s of its scripted press
# (implicit, lockstep: 130 frames); its picture with the panel comes from a realtime session instead (the
# simulation and haptic threads as in a window; 110 drawn frames, about 1.1 s of the press here, depending on
# the machine's speed). About 12 minutes in all.
VIEW_SHOT = $(BUILD_DIR)/vascsim -q view
IMAGES ?= docs/images
screenshots: build
	$(VIEW_SHOT) scenes/hand-dorsal-vein.json --frames 1 --size 800x800 --yaw 90 --pitch 10 --lao 90 \
	  --screenshot $(IMAGES)/view-hand-dorsal-vein.png --fluoro-screenshot $(IMAGES)/view-hand-dorsal-vein-fluoro.png
	$(VIEW_SHOT) scenes/aorta-bent.json --frames 1 --size 800x800 --yaw 20 --pitch 20 --lao 20 \
	  --screenshot $(IMAGES)/view-aorta-bent.png --fluoro-screenshot $(IMAGES)/view-aorta-bent-fluoro.png
	$(VIEW_SHOT) scenes/retinal-artery-twice-bent.json --frames 1 --size 800x800 --yaw 30 --pitch 20 --lao 30 \
	  --screenshot $(IMAGES)/view-retinal-artery-twice-bent.png \
	  --fluoro-screenshot $(IMAGES)/view-retinal-artery-twice-bent-fluoro.png
	$(VIEW_SHOT) scenes/aorta-vmtk.json --colour-map --frames 1 --size 800x800 --yaw -30 --pitch 10 --lao -30 \
	  --screenshot $(IMAGES)/view-aorta-vmtk.png --fluoro-screenshot $(IMAGES)/view-aorta-vmtk-fluoro.png
	$(VIEW_SHOT) scenes/realtime/hand-dorsal-vein-catheter.json --play --frames 130 --size 1024x640 --yaw 60 \
	  --pitch 20 --lao 60 --screenshot $(IMAGES)/view-vein-catheter.png \
	  --fluoro-screenshot $(IMAGES)/view-vein-catheter-fluoro.png
	$(VIEW_SHOT) scenes/realtime/hand-dorsal-vein-catheter.json --play --realtime --frames 110 --size 1024x640 \
	  --yaw 60 --pitch 20 --hud --screenshot $(IMAGES)/view-vein-catheter-hud.png

# docs/performance.md's viewer table: frames per second with the split (simulation, MLS map, normals, upload,
# draw) of the real-time scenes at the default window size, headless with the threads of a window (minutes).
VIEW_BENCH_SCENES ?= scenes/realtime/hand-dorsal-vein-catheter.json scenes/realtime/hand-dorsal-vein.json \
  scenes/realtime/aorta-bent.json scenes/realtime/retinal-artery-twice-bent.json
view-bench: build
	@uptime
	@for s in $(VIEW_BENCH_SCENES); do for m in lit fluoro; do \
	  $(BUILD_DIR)/vascsim -q view $$s --realtime --measure --frames 300 --mode $$m --screenshot /dev/null || exit 1; \
	done; done
	@uptime

compare-models: build
	$(PYTHON) scripts/compare_models.py --vascsim $(BUILD_DIR)/vascsim --out out/compare-models

# docs/validation.md's xpbd-vs-quasi_static table on the cantilever (a few minutes).
xpbd-convergence: build
	$(PYTHON) scripts/xpbd_convergence.py --vascsim $(BUILD_DIR)/vascsim --scene scenes/cantilever.json \
	  --configs 1x1,2x1,4x1,8x1,16x1,32x1,1x8,2x4,4x2,8x2,8x4,8x8 --duration 0.6 --ramp 0.1 --damping 60 \
	  --output-interval 0.05 --force-region clamp --displacement-region tip --out out/xpbd-convergence/cantilever

# docs/validation.md's cantilever convergence table (test T9).
cantilever-table: build
	$(BUILD_DIR)/vascsim validate cantilever --out out/cantilever-table

# The paper's comparison experiments (docs/replicate.md): Fig. 10, the force-displacement curves of the models on
# the catheter scene against the quasi_static reference with the RMS error table, and Figs. 11-12, time per step
# and frames per second against node count. Every model run and every timing point is its own `vascsim`
# process (JSON in, JSON out); GNU parallel runs them when it is installed (model runs JOBS at a time, timing
# points one at a time so they do not time each other), a plain loop otherwise; a last step merges them into
# one CSV, table and figure. Finished runs and points are kept and reused: delete the folder to start over.
comma := ,
empty :=
space := $(empty) $(empty)
FIG10_SCENE   ?= scenes/hand-dorsal-vein-catheter.json
FIG10_MODELS  ?= implicit xpbd mass_spring fem_quasi_newton tensor_mass filling pbd_viscoelastic
FIG10_OUT     ?= out/fig10
TIMING_SCENE  ?= scenes/vein-indent.json
TIMING_MODELS ?= implicit xpbd mass_spring fem_quasi_newton tensor_mass filling pbd_viscoelastic
TIMING_NODES  ?= 1000 2000 4000
TIMING_OUT    ?= out/timing
HAVE_PARALLEL := $(shell command -v parallel 2>/dev/null)

experiments: fig10 timing

fig10: build
ifneq ($(HAVE_PARALLEL),)
	parallel --will-cite --halt now,fail=1 -j $(JOBS) 'grep -qs force_displacement $(FIG10_OUT)/{}/summary.json || $(BUILD_DIR)/vascsim -q -j 1 experiment force-displacement $(FIG10_SCENE) --set model={} --out $(FIG10_OUT)/{} --no-plot' ::: quasi_static $(FIG10_MODELS)
else
	@for m in quasi_static $(FIG10_MODELS); do grep -qs force_displacement $(FIG10_OUT)/$$m/summary.json || \
	  $(BUILD_DIR)/vascsim -q -j 1 experiment force-displacement $(FIG10_SCENE) --set model=$$m --out $(FIG10_OUT)/$$m --no-plot \
	  || exit 1; done
endif
	$(BUILD_DIR)/vascsim experiment force-displacement $(FIG10_SCENE) --models $(subst $(space),$(comma),$(FIG10_MODELS)) --reuse --out $(FIG10_OUT)

timing: build
ifneq ($(HAVE_PARALLEL),)
	parallel --will-cite --halt now,fail=1 -j 1 $(BUILD_DIR)/vascsim -q experiment timing $(TIMING_SCENE) --point {1}:{2} --reuse --out $(TIMING_OUT) ::: $(TIMING_MODELS) ::: $(TIMING_NODES)
else
	@for m in $(TIMING_MODELS); do for n in $(TIMING_NODES); do \
	  $(BUILD_DIR)/vascsim -q experiment timing $(TIMING_SCENE) --point $$m:$$n --reuse --out $(TIMING_OUT) || exit 1; done; done
endif
	$(BUILD_DIR)/vascsim experiment timing $(TIMING_SCENE) --merge --models $(subst $(space),$(comma),$(TIMING_MODELS)) \
	  $(if $(wildcard $(FIG10_OUT)/rms_error.json),--force-errors $(FIG10_OUT)/rms_error.json) --out $(TIMING_OUT)

# The fuzz targets of docs/reliability.md (libFuzzer with ASan + UBSan; clang-14 and libclang-rt-14-dev, which
# scripts/install-deps.sh installs): the library in its own clang build folder, then each target for FUZZ_SECONDS
# (default 600 s; 1,000,000 executions took 104 s for trajectories, 169 s for scenes and 318 s for recordings here,
# and about half an hour for meshes: docs/reliability.md) from a seed corpus made from the bundled files
# (scripts/fuzz_corpus.py). Inputs that found new coverage collect in out/fuzz/corpus-<target>, a crash in
# out/fuzz/crash-<target>-*; not committed. Not part of `make test` (which runs each harness for a few seconds).
FUZZ_DIR     ?= build-fuzz
FUZZ_SECONDS ?= 600
FUZZ_TARGETS ?= scene mesh trajectory recording
fuzz: deps
	cmake -S . -B $(FUZZ_DIR) -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++-14 \
	  -DVASCSIM_FUZZ=ON -DVASCSIM_SHARED=OFF -DVASCSIM_BUILD_TESTS=OFF -DVASCSIM_BUILD_BENCH=OFF -DVASCSIM_BUILD_VIEWER=OFF \
	  -DVASCSIM_WERROR=ON
	cmake --build $(FUZZ_DIR) -j $(JOBS) --target $(addprefix fuzz_,$(FUZZ_TARGETS))
	@for t in $(FUZZ_TARGETS); do \
	  $(PYTHON) scripts/fuzz_corpus.py $$t out/fuzz/seeds-$$t && mkdir -p out/fuzz/corpus-$$t && \
	  LSAN_OPTIONS=suppressions=fuzz/lsan-suppressions.txt $(FUZZ_DIR)/fuzz/fuzz_$$t out/fuzz/corpus-$$t out/fuzz/seeds-$$t -max_total_time=$(FUZZ_SECONDS) \
	    -max_len=65536 -rss_limit_mb=4096 -timeout=20 -print_final_stats=1 -artifact_prefix=out/fuzz/crash-$$t- \
	    2> out/fuzz/$$t.log; status=$$?; grep -E '^stat::number_of_executed_units|^#[0-9]+.*DONE' out/fuzz/$$t.log; \
	  if [ $$status -ne 0 ]; then tail -n 40 out/fuzz/$$t.log; exit 1; fi; done

# The soak test of docs/reliability.md (not in CI): a realtime haptic session on SOAK_SCENE with a wandering tool
# (random but bounded motion, seeded) for SOAK_SECONDS of wall clock; soak.json and soak.md in SOAK_OUT. Run it on
# an otherwise idle machine: the jitter it reports is the machine's too.
SOAK_SCENE   ?= scenes/realtime/hand-dorsal-vein-catheter.json
SOAK_SECONDS ?= 3600
SOAK_SEED    ?= 1
SOAK_OUT     ?= out/soak
soak: build
	$(BUILD_DIR)/vascsim soak $(SOAK_SCENE) --seconds $(SOAK_SECONDS) --seed $(SOAK_SEED) --out $(SOAK_OUT)

format:
	clang-format-14 -i $$(git ls-files '*.cpp' '*.hpp')

clean:
	rm -rf $(BUILD_DIR) $(ASAN_DIR) $(PACKAGE_DIR)
