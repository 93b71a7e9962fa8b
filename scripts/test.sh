#!/usr/bin/env bash
# One command from a fresh Debian 12 machine to a tested build: installs what is missing, builds, runs ctest.
# Exits with ctest's status.
#
#   bash scripts/test.sh             (extra arguments go to ctest, e.g. -R io_)
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
bash scripts/build.sh

# The MPI tests oversubscribe the cores; each declares its ranks (PROCESSORS), so with -j N ctest never
# runs more ranks at once than N. See docs/foundation.md for the -j1 / -j2 measurements.
jobs=${CTEST_PARALLEL_LEVEL:-$(nproc)}
status=0
build_dir=${BUILD_DIR:-build}
(cd "$build_dir" && ctest --output-on-failure -j"$jobs" "$@") | tee "$build_dir/ctest.log" || status=$?
echo
grep -E "^[0-9]+% tests passed" "$build_dir/ctest.log" || echo "test.sh: ctest printed no summary line"
exit "$status"
