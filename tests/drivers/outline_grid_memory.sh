#!/bin/bash
# A piece given by its outline with a grid of 26000 x 26000 (676 million particles, just within what a 32-bit
# PetscInt indexes) is refused by the run's memory check (exit 2, naming the grid and the memory it needs), with the
# process limited to 1.5 GB of address space: the scene reader's check of the outline's grid for folded cells holds
# two rows of it at a time (src/pattern.c, PatternFindFoldedCell). Before (issue 48's sweep of allocations sized from
# input) the reader meshed the whole grid first, 16 bytes a particle (10.8 GB here), before the memory check: under
# the limit an allocation failure with PETSc's traceback.
#
#   outline_grid_memory.sh
set -euo pipefail
tests=$(cd "$(dirname "$0")/.." && pwd)
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
cat > "$dir/huge_outline_grid.yaml" <<'YAML'
name: huge_outline_grid
fabrics: {net: {density: 0.2, stretch: 1000}}
pieces:
  - name: panel
    fabric: net
    grid: [26000, 26000]
    boundaries: {bottom: [[0, 0], [1, 0]], right: [[1, 0], [1, 1]], top: [[0, 1], [1, 1]], left: [[0, 0], [0, 1]]}
YAML
ulimit -v 1500000
bash "$tests/drivers/expect_error.sh" --status 2 1 "$dir/huge_outline_grid.yaml" "the grids ('panel' 26000 x 26000) give 676000000 particles" "GB of memory on a node"
