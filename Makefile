# The two commands of the README: `make run` and `make test`. Both install the Debian
# packages they need first (`make deps`), so they work on a fresh Debian 12 machine.
BUILD_DIR ?= build
JOBS ?= $(shell nproc)
PACKAGES = cmake g++ make libeigen3-dev libspectra-dev libcgal-dev libgeographiclib-dev \
           libyaml-cpp-dev libhdf5-dev pkg-config libdeflate-dev catch2 libcli11-dev libopenmpi-dev openmpi-bin \
           libopenblas-dev liblapacke-dev \
           libocct-data-exchange-dev libocct-modeling-algorithms-dev libocct-modeling-data-dev libocct-foundation-dev \
           libocct-visualization-dev libocct-ocaf-dev libtbb-dev \
           python3-h5py python3-matplotlib python3-numpy
# ParaView, only to test that what users open in it loads (pvbatch under Xvfb, Mesa's
# software OpenGL); without recommends it is about 150 MB.
VIEW_PACKAGES = paraview python3-paraview xvfb xauth libgl1-mesa-dri
SUDO = $(shell [ "$$(id -u)" -eq 0 ] || echo sudo)
EXAMPLE ?= cases/examples/cubesat-3u.yaml

.PHONY: deps build run test sanitize bench bench-scale bench-factored-thermal clean

deps:
	@missing=$$(for p in $(PACKAGES); do dpkg-query -W -f='$${Status}\n' $$p 2>/dev/null | grep -q 'install ok installed' || echo $$p; done); \
	if [ -n "$$missing" ]; then \
	  if [ -n "$(SUDO)" ]; then echo "make deps: not root, installing with sudo:$$missing"; fi; \
	  $(SUDO) apt-get update -qq && DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -qq $$missing; \
	fi
	@missing=$$(for p in $(VIEW_PACKAGES); do dpkg-query -W -f='$${Status}\n' $$p 2>/dev/null | grep -q 'install ok installed' || echo $$p; done); \
	if [ -n "$$missing" ]; then \
	  $(SUDO) apt-get update -qq && DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -qq --no-install-recommends $$missing; \
	fi

build: deps
	cmake -S . -B $(BUILD_DIR) -DCMAKE_BUILD_TYPE=Release
	cmake --build $(BUILD_DIR) -j $(JOBS)

run: build
	./$(BUILD_DIR)/radnet run $(EXAMPLE) -o $(BUILD_DIR)/$(notdir $(basename $(EXAMPLE))).h5

test: build
	cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS)

# Debug build with AddressSanitizer and UndefinedBehaviorSanitizer, all tests.
sanitize: deps
	cmake -S . -B build-sanitize -DCMAKE_BUILD_TYPE=Debug -DRADNET_SANITIZE=ON
	cmake --build build-sanitize -j $(JOBS)
	cd build-sanitize && UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 ctest --output-on-failure -j $(JOBS)

# radnet against n up to 100,002 nodes (about 9 minutes on 2 cores): docs/scale-benchmark.md
# Temperatures on a factored GR against the dense LU, 1,000–6,000 nodes (issue 32), ~10 min.
bench-factored-thermal: build
	./$(BUILD_DIR)/bench/bench_factored_thermal docs/factored-thermal-benchmark.md

bench-scale: build
	/usr/bin/python3 bench/bench_scale.py $(BUILD_DIR)/radnet docs/scale-benchmark.md \
	  bench/cases/satellite-1602.yaml bench/cases/satellite-6402.yaml bench/cases/satellite-19202.yaml \
	  bench/cases/satellite-100002.yaml --defaults bench/cases/satellite-1602.yaml bench/cases/satellite-6402.yaml \
	  bench/cases/satellite-19202.yaml

bench: build
	./$(BUILD_DIR)/bench/bench_solver docs/solver-benchmark.md docs/solver-eigenvalues.csv
	/usr/bin/python3 bench/plot_solver_benchmark.py docs/solver-benchmark.md docs/solver-eigenvalues.csv \
	  docs/solver-benchmark.png
	./$(BUILD_DIR)/bench/bench_view_factors docs/view-factor-benchmark.md
	./$(BUILD_DIR)/bench/bench_ray_caster docs/ray-caster-benchmark.md
	./$(BUILD_DIR)/bench/bench_loads docs/loads-benchmark.md bench/cases/satellite-1602.yaml bench/cases/satellite-6402.yaml
	# The loads stage against an older build, nadir, Sun-pointing and inertial (issue 31; about 10 minutes):
	# make bench BASELINE=path/to/older/radnet
	if [ -n "$(BASELINE)" ]; then /usr/bin/python3 bench/bench_loads_builds.py $(BASELINE) $(BUILD_DIR)/radnet \
	  docs/loads-build-comparison.md bench/cases/satellite-1602.yaml bench/cases/satellite-6402.yaml \
	  --once bench/cases/satellite-19202.yaml; fi
	/usr/bin/python3 bench/bench_articulation.py $(BUILD_DIR)/radnet docs/articulation-benchmark.md \
	  bench/cases/tracking-wings-2102.yaml bench/cases/tracking-wings-2006.yaml bench/cases/steered-dish-1602.yaml
	./$(BUILD_DIR)/bench/bench_thermal docs/thermal-benchmark.md
	./$(BUILD_DIR)/bench/bench_design_cases bench/cases/satellite-1602-design.yaml docs/design-cases-benchmark.md \
	  bench/cases/satellite-6402.yaml
	# View3D, the reference open tool, built only to run beside radnet (never linked).
	if [ -x ../shared/peers/view3d/build.sh ] || [ -f ../shared/peers/view3d/build.sh ]; then \
	  bash ../shared/peers/view3d/build.sh $(BUILD_DIR)/view3d >/dev/null; fi
	./$(BUILD_DIR)/bench/bench_exact_view_factors docs/exact-view-factor-benchmark.md \
	  docs/exact-view-factor-benchmark.csv $$( [ -x $(BUILD_DIR)/view3d/view3d ] && echo $(BUILD_DIR)/view3d/view3d )
	/usr/bin/python3 bench/plot_exact_benchmark.py docs/exact-view-factor-benchmark.csv \
	  docs/exact-view-factor-benchmark.png
	# View factors at default settings on rooms, cylinders, satellites and a CAD assembly (issue 30).
	/usr/bin/python3 bench/bench_view_factor_defaults.py $(BUILD_DIR)/radnet docs/view-factor-defaults-benchmark.md \
	  $$( [ -x $(BUILD_DIR)/view3d/view3d ] && echo $(BUILD_DIR)/view3d/view3d )
	# Writing the n × n matrices: HDF5's filter against radnet's parallel chunks (issue 12).
	# (Past 5,000 nodes a sparse network is written as CSR groups, no (n, n) dataset: the
	# 1,602-node satellite is the sparse case with (n, n) datasets, the room the dense one.)
	./$(BUILD_DIR)/radnet run bench/cases/satellite-1602.yaml -o $(BUILD_DIR)/satellite-1602.h5 -q
	./$(BUILD_DIR)/radnet run bench/cases/room-32.yaml -o $(BUILD_DIR)/room-32.h5 -q
	./$(BUILD_DIR)/bench/bench_hdf5_write docs/hdf5-write-benchmark.md $(BUILD_DIR)/satellite-1602.h5 \
	  $(BUILD_DIR)/room-32.h5
	# Every band-solve method on the satellites' own networks, n = 1,602 … 19,202 (about 25 minutes;
	# the 1,602-node result is the one written above).
	./$(BUILD_DIR)/radnet run bench/cases/satellite-6402.yaml -o $(BUILD_DIR)/satellite-6402.h5 -q
	./$(BUILD_DIR)/radnet run bench/cases/satellite-19202.yaml -o $(BUILD_DIR)/satellite-19202.h5 -q
	./$(BUILD_DIR)/bench/bench_solver_satellites docs/solver-satellite-benchmark.md \
	  docs/solver-satellite-eigenvalues.csv $(BUILD_DIR)/satellite-1602.h5 $(BUILD_DIR)/satellite-6402.h5 \
	  $(BUILD_DIR)/satellite-19202.h5
	/usr/bin/python3 bench/plot_solver_benchmark.py docs/solver-satellite-benchmark.md \
	  docs/solver-satellite-eigenvalues.csv docs/solver-satellite-benchmark.png
	# End to end against n, before and with the error budget (about 15 minutes).
	/usr/bin/python3 bench/bench_end_to_end.py $(BUILD_DIR)/radnet docs/benchmarks.md \
	  bench/cases/satellite-1602.yaml bench/cases/satellite-6402.yaml bench/cases/satellite-19202.yaml
	# Eigen's dense kernels against Debian's threaded OpenBLAS (issue 12; needs libopenblas-dev, liblapacke-dev).
	if [ -x $(BUILD_DIR)/bench/bench_dense_kernels_openblas ]; then \
	  /usr/bin/python3 bench/bench_blas.py $(BUILD_DIR) docs/blas-benchmark.md; fi
	# One process against two MPI ranks, bit for bit, and the cluster scaling model (issue 15; about 25 minutes).
	/usr/bin/python3 bench/bench_mpi.py $(BUILD_DIR)/radnet docs/mpi-benchmark.md \
	  bench/cases/satellite-1602.yaml bench/cases/satellite-1602-design.yaml bench/cases/satellite-6402.yaml
	# The sparse network path against the dense one on the same G (issue 32; a minute).
	./$(BUILD_DIR)/radnet run bench/cases/satellite-1602.yaml -o $(BUILD_DIR)/sd-1602.h5 -q
	./$(BUILD_DIR)/radnet run bench/cases/satellite-6402.yaml -o $(BUILD_DIR)/sd-6402.h5 -q
	./$(BUILD_DIR)/bench/bench_sparse_dense docs/sparse-dense-benchmark.md $(BUILD_DIR)/sd-1602.h5 $(BUILD_DIR)/sd-6402.h5
	# Memory per rank with the rows shared out: 50,102 nodes at the defaults, 1 process and 2 ranks (issue 32; about 15 minutes).
	/usr/bin/python3 bench/bench_mpi_memory.py $(BUILD_DIR)/radnet docs/mpi-memory-benchmark.md \
	  bench/cases/satellite-50102.yaml --ranks 2 --defaults

clean:
	rm -rf $(BUILD_DIR) build-sanitize
