# shellcheck shell=bash
# Shared set-up for scripts/demo.sh, scripts/test.sh and scripts/bench.sh (sourced, not run):
#   1. checks that the Debian packages the caller needs are installed (softbody_setup demo: the
#      build's and the demo's; softbody_setup: those and the tests'), and installs the missing
#      ones when running as root (or prints the apt-get line and exits 1);
#   2. configures build/ once (CMake + Ninja, Release) and builds it (fast when up to date). A
#      folder the demo configures first leaves the tests and benchmarks out; the tests' set-up
#      turns them on again.
#
# Variables a caller may set beforehand:
#   SOFTBODY_BUILD_DIR   build folder (default: <repo>/build)
#   SOFTBODY_JOBS        parallel build jobs (default: nproc)
#   SOFTBODY_SKIP_APT=1  skip the package check (e.g. a machine with ParaView built from source)
#   SOFTBODY_NO_CCACHE=1 configure without ccache even where it is installed (used when present)
#   SOFTBODY_CMAKE_ARGS  array of extra CMake arguments for the configure (test.sh --asan/--tsan
#                        set -DSOFTBODY_SANITIZER=...); a cached build folder is configured
#                        again when they are given
#
# Defines for the caller: SOFTBODY_ROOT, SOFTBODY_BUILD_DIR, SOFTBODY_PLUGIN_FILE, and the
# functions softbody_setup, softbody_check_packages, softbody_configure_and_build.

SOFTBODY_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
SOFTBODY_BUILD_DIR="${SOFTBODY_BUILD_DIR:-${SOFTBODY_ROOT}/build}"
SOFTBODY_PLUGIN_FILE="${SOFTBODY_BUILD_DIR}/lib/paraview-5.11/plugins/SoftBody/SoftBody.so"

# Debian bookworm packages the build and the demo need, one line per reason.
SOFTBODY_PACKAGES=(
  cmake ninja-build g++ pkg-config              # the build tools
  paraview-dev python3-paraview python3-numpy   # ParaView 5.11 headers and CMake config, pvpython
  libdouble-conversion-dev libopenmpi-dev       # required by paraview-dev's CMake config
  libtbb-dev libeigen3-dev libtet1.5-dev        # core/: threads, linear algebra, TetGen
  libsuitesparse-dev libopenblas0-serial        # core/: CHOLMOD sparse Cholesky on a serial BLAS
  libhypre-dev                                  # core/: BoomerAMG, the AlgebraicMultigrid preconditioner
  libegl-dev libopengl-dev libgl-dev            # gpu/: headless EGL + OpenGL compute
  libegl-mesa0 libgl1-mesa-dri                  # Mesa EGL + llvmpipe, so GPU tests run without a GPU
  xvfb xauth                                    # rendering (demo, tests) without a display
  python3-pil                                   # the demo's animated GIF
  qtxmlpatterns5-dev-tools qttools5-dev         # the plugin's help pages (xmlpatterns, qhelpgenerator)
  paraview libqt5svg5                           # the GUI, to open the demo's state; tests/gui (svg: icons)
  libqt5svg5-dev libqt5opengl5-dev              # the GUI side of the plugin (ParaView's pqCore CMake config)
)
# What the tests and benchmarks add.
SOFTBODY_TEST_PACKAGES=(
  libgtest-dev libbenchmark-dev                 # tests/unit, tests/bench
  openmpi-bin                                   # mpirun, for the python.mpi test (mpirun -np 2 pvbatch)
)

softbody_log() { printf '[softbody] %s\n' "$*" >&2; }

# Prints the packages of SOFTBODY_PACKAGES that are not installed, one per line.
softbody_missing_packages() {
  local pkg status
  for pkg in "${SOFTBODY_PACKAGES[@]}"; do
    status="$(dpkg-query -W -f='${db:Status-Status}' "${pkg}" 2>/dev/null || true)"
    if [[ "${status}" != "installed" ]]; then
      printf '%s\n' "${pkg}"
    fi
  done
}

softbody_check_packages() {
  if [[ "${SOFTBODY_SKIP_APT:-0}" == "1" ]]; then
    softbody_log "SOFTBODY_SKIP_APT=1: not checking Debian packages"
    return 0
  fi
  if ! command -v dpkg-query >/dev/null 2>&1; then
    softbody_log "dpkg-query not found: this is not a Debian-like system."
    softbody_log "Install the equivalents of: ${SOFTBODY_PACKAGES[*]}"
    softbody_log "then run again with SOFTBODY_SKIP_APT=1."
    exit 1
  fi
  local missing
  mapfile -t missing < <(softbody_missing_packages)
  if [[ ${#missing[@]} -eq 0 ]]; then
    return 0
  fi
  softbody_log "missing Debian packages: ${missing[*]}"
  if [[ "$(id -u)" -eq 0 ]]; then
    softbody_log "installing them (apt-get, as root)"
    export DEBIAN_FRONTEND=noninteractive
    apt-get update
    apt-get install -y --no-install-recommends "${missing[@]}"
    mapfile -t missing < <(softbody_missing_packages)
    if [[ ${#missing[@]} -ne 0 ]]; then
      softbody_log "still missing after apt-get install: ${missing[*]}"
      exit 1
    fi
  else
    softbody_log "not running as root; install them with:"
    printf '\n    sudo apt-get update && sudo apt-get install -y --no-install-recommends %s\n\n' \
      "${missing[*]}" >&2
    softbody_log "then run this script again."
    exit 1
  fi
}

softbody_configure_and_build() {
  local jobs="${SOFTBODY_JOBS:-$(nproc)}"
  local -a extra=()
  if declare -p SOFTBODY_CMAKE_ARGS >/dev/null 2>&1; then
    extra=("${SOFTBODY_CMAKE_ARGS[@]}")
  fi
  if [[ ! -f "${SOFTBODY_BUILD_DIR}/CMakeCache.txt" ]]; then
    # A compiler cache, when the machine has one, makes rebuilds in fresh folders cheap; it
    # never changes what is built.
    if command -v ccache >/dev/null 2>&1 && [[ -z "${SOFTBODY_NO_CCACHE:-}" ]]; then
      extra+=("-DCMAKE_C_COMPILER_LAUNCHER=ccache" "-DCMAKE_CXX_COMPILER_LAUNCHER=ccache")
    fi
    softbody_log "configuring ${SOFTBODY_BUILD_DIR} ${extra[*]}"
    cmake -S "${SOFTBODY_ROOT}" -B "${SOFTBODY_BUILD_DIR}" -G Ninja -DCMAKE_BUILD_TYPE=Release \
      "${extra[@]}"
  elif [[ ${#extra[@]} -gt 0 ]]; then
    # Make sure the cached folder has these settings (a no-op configure when it already does).
    cmake -S "${SOFTBODY_ROOT}" -B "${SOFTBODY_BUILD_DIR}" "${extra[@]}" >/dev/null
  elif [[ ! -f "${SOFTBODY_BUILD_DIR}/build.ninja" && ! -f "${SOFTBODY_BUILD_DIR}/Makefile" ]]; then
    # A cache from an earlier configure that failed: configure again with the cached generator.
    softbody_log "re-configuring ${SOFTBODY_BUILD_DIR} (an earlier configure did not finish)"
    cmake -S "${SOFTBODY_ROOT}" -B "${SOFTBODY_BUILD_DIR}"
  fi
  softbody_log "building ${SOFTBODY_BUILD_DIR} with ${jobs} jobs"
  cmake --build "${SOFTBODY_BUILD_DIR}" -j"${jobs}"
  if [[ ! -f "${SOFTBODY_PLUGIN_FILE}" ]]; then
    softbody_log "the build finished but ${SOFTBODY_PLUGIN_FILE} is missing"
    exit 1
  fi
}

# softbody_setup [demo]: the packages and the build the caller needs; without `demo`, the tests'
# and benchmarks' too.
softbody_setup() {
  cd "${SOFTBODY_ROOT}" || exit 1
  if [[ "${1:-}" == "demo" ]]; then
    if [[ ! -f "${SOFTBODY_BUILD_DIR}/CMakeCache.txt" ]]; then
      SOFTBODY_CMAKE_ARGS+=("-DSOFTBODY_BUILD_TESTING=OFF" "-DSOFTBODY_BUILD_BENCHMARKS=OFF")
    fi
  else
    SOFTBODY_PACKAGES+=("${SOFTBODY_TEST_PACKAGES[@]}")
    SOFTBODY_CMAKE_ARGS+=("-DSOFTBODY_BUILD_TESTING=ON" "-DSOFTBODY_BUILD_BENCHMARKS=ON")
  fi
  softbody_check_packages
  softbody_configure_and_build
}
