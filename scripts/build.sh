#!/usr/bin/env bash
# Configures and builds the catkin workspace whose src/ is this repository.
#   scripts/build.sh                 build everything into .ws/build and .ws/devel
#   scripts/build.sh --tests         also build every test target
#   scripts/build.sh --sanitize PKG… build PKG's unit tests with ASan+UBSan into .ws/build_sanitize
#   scripts/build.sh --only PKG…     build PKG (and its tests) alone into .ws/build_PKG, .ws/devel_PKG
#                                    (BUILD_NAME=NAME: into .ws/build_NAME, .ws/devel_NAME instead)
# Environment: JOBS (default 2), BUILD_TYPE (default Release).
set -euo pipefail
src="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
jobs="${JOBS:-2}"
build_type="${BUILD_TYPE:-Release}"
export PATH="/usr/bin:$PATH"   # Debian's python3 (catkin_pkg, rospy), not a pyenv one
mkdir -p "$src/.ws"
touch "$src/.ws/CATKIN_IGNORE"
# The catkin top-level CMakeLists.txt is a link into Debian's catkin (tracked by git; re-created if removed).
[ -L "$src/CMakeLists.txt" ] || ln -s /usr/share/catkin/cmake/toplevel.cmake "$src/CMakeLists.txt"
[ -e "$src/CMakeLists.txt" ] || { echo "[build] catkin is not installed: run scripts/install_deps.sh" >&2; exit 1; }

# ccache (a listed Debian package) keeps compiled objects between builds and between clones of the repository:
# paths below the repository are hashed relative to it, so a fresh clone in another folder reuses the objects of
# earlier builds on the same machine. CCACHE_DISABLE=1 turns it off.
if command -v ccache >/dev/null; then
  export CCACHE_BASEDIR="$src" CCACHE_NOHASHDIR=true
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
else
  launcher=()
fi

configure() {  # $1 build dir, $2 devel dir, rest: extra cmake args
  local b="$1" d="$2"; shift 2
  # A build folder configured with the same arguments is not configured again (a minute of catkin's CMake on 2
  # cores): its Makefiles re-run CMake themselves when a CMakeLists.txt changed. A new package is not seen then:
  # remove .ws/build.configure.args (or the build folder) to configure again.
  local args="$d $build_type ${launcher[*]} $*"
  if [ -f "$b/Makefile" ] && [ "$(cat "$b.configure.args" 2>/dev/null)" = "$args" ]; then return 0; fi
  rm -f "$b.configure.args"
  # catkin caches the test environment at configure time and leaves the devel python folder out of PYTHONPATH
  # when it does not exist yet: python tests would then not find the workspace's messages on a fresh build.
  mkdir -p "$d/lib/python3/dist-packages"
  cmake -S "$src" -B "$b" -DCATKIN_DEVEL_PREFIX="$d" -DCMAKE_BUILD_TYPE="$build_type" \
    -DPYTHON_EXECUTABLE=/usr/bin/python3 -DCATKIN_ENABLE_TESTING=ON -DCMAKE_INSTALL_PREFIX="$src/.ws/install" \
    "${launcher[@]}" "$@" >"$b.configure.log" 2>&1 || {
    cat "$b.configure.log"; echo "[build] cmake configure failed" >&2; exit 1; }
  echo "$args" >"$b.configure.args"
}

# Runs make with its full output in "$1.make.log" and prints a progress line each time another tenth of the
# targets is done, and the errors when it fails.
build() {  # $1 build dir, rest: make targets
  local b="$1"; shift
  echo "[build] make $* in ${b#"$src"/} (full log: ${b#"$src"/}.make.log)"
  if ! make -C "$b" -j"$jobs" "$@" 2>&1 | tee "$b.make.log" | awk '
      match($0, /^\[ *[0-9]+%\]/) {
        pct = substr($0, RSTART + 1, RLENGTH - 3) + 0
        if (pct >= last + 10 || (pct == 100 && last < 100)) {
          last = pct - pct % 10; if (pct == 100) last = 100
          printf "[build] %3d%%  %s\n", pct, substr($0, RLENGTH + 2); fflush()
        }
      }'; then
    grep -E "error|Error|\*\*\*" "$b.make.log" | head -40 >&2
    echo "[build] make failed: see ${b#"$src"/}.make.log" >&2
    exit 1
  fi
}

mode="${1:-}"
case "$mode" in
  --sanitize)
    shift
    pkgs="$(IFS=';'; echo "$*")"
    b="$src/.ws/build_sanitize"; mkdir -p "$b"
    flags="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer"
    configure "$b" "$src/.ws/devel_sanitize" -DCMAKE_BUILD_TYPE=Debug -DCATKIN_WHITELIST_PACKAGES="$pkgs" \
      -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_C_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" \
      -DCMAKE_SHARED_LINKER_FLAGS="-fsanitize=address,undefined"
    build "$b" tests  # the unit tests and the libraries they link; nodes and benches are not run here
    ;;
  --only)
    shift
    # thorvald_testing (the Python rostests' helpers) comes with every partial build: tests import it.
    pkgs="$(IFS=';'; echo "$*");thorvald_testing"
    name="${BUILD_NAME:-$1}"  # BUILD_NAME: a build folder of its own for the same package
    b="$src/.ws/build_$name"; mkdir -p "$b"
    configure "$b" "$src/.ws/devel_$name" -DCATKIN_WHITELIST_PACKAGES="$pkgs"
    build "$b" all tests
    ;;
  --tests|"")
    b="$src/.ws/build"; mkdir -p "$b"
    configure "$b" "$src/.ws/devel"
    build "$b" all
    if [ "$mode" = "--tests" ]; then build "$b" tests; fi
    ;;
  *) echo "usage: $0 [--tests | --only PKG... | --sanitize PKG...]" >&2; exit 2 ;;
esac
echo "[build] ok"
