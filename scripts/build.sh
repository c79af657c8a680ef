#!/usr/bin/env bash
# Configures and builds the catkin workspace whose src/ is this repository.
#   scripts/build.sh                 build everything into .ws/build and .ws/devel
#   scripts/build.sh --tests         also build every test target
#   scripts/build.sh --sanitize PKG… build PKG's unit tests with ASan+UBSan into .ws/build_sanitize
#   scripts/build.sh --only PKG…     build PKG (and its tests) alone into .ws/build_PKG, .ws/devel_PKG
# Environment: JOBS (default 2), BUILD_TYPE (default Release).
set -euo pipefail
src="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
jobs="${JOBS:-2}"
build_type="${BUILD_TYPE:-Release}"
export PATH="/usr/bin:$PATH"   # Debian's python3 (catkin_pkg, rospy), not a pyenv one
mkdir -p "$src/.ws"
touch "$src/.ws/CATKIN_IGNORE"
[ -e "$src/CMakeLists.txt" ] || ln -s /usr/share/catkin/cmake/toplevel.cmake "$src/CMakeLists.txt"

configure() {  # $1 build dir, $2 devel dir, rest: extra cmake args
  local b="$1" d="$2"; shift 2
  # catkin caches the test environment at configure time and leaves the devel python folder out of PYTHONPATH
  # when it does not exist yet: python tests would then not find the workspace's messages on a fresh build.
  mkdir -p "$d/lib/python3/dist-packages"
  cmake -S "$src" -B "$b" -DCATKIN_DEVEL_PREFIX="$d" -DCMAKE_BUILD_TYPE="$build_type" \
    -DPYTHON_EXECUTABLE=/usr/bin/python3 -DCATKIN_ENABLE_TESTING=ON "$@" >"$b.configure.log" 2>&1 || {
    cat "$b.configure.log"; echo "[build] cmake configure failed" >&2; exit 1; }
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
    make -C "$b" -j"$jobs" all tests
    ;;
  --only)
    shift
    pkgs="$(IFS=';'; echo "$*")"
    b="$src/.ws/build_$1"; mkdir -p "$b"
    configure "$b" "$src/.ws/devel_$1" -DCATKIN_WHITELIST_PACKAGES="$pkgs"
    make -C "$b" -j"$jobs" all tests
    ;;
  --tests|"")
    b="$src/.ws/build"; mkdir -p "$b"
    configure "$b" "$src/.ws/devel"
    make -C "$b" -j"$jobs" all
    if [ "$mode" = "--tests" ]; then make -C "$b" -j"$jobs" tests; fi
    ;;
  *) echo "usage: $0 [--tests | --only PKG... | --sanitize PKG...]" >&2; exit 2 ;;
esac
echo "[build] ok"
