#!/usr/bin/env bash
# Configures and builds clothsim into build/ (optimised, with debug information): build/clothsim and the tests.
#
#   bash scripts/build.sh            (BUILD_DIR=... to build elsewhere; extra arguments go to cmake's configure step)
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir=${BUILD_DIR:-build}
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo "$@"
cmake --build "$build_dir" -j"$(nproc)"
