/* Quality of an assembled garment, measured at the end of a run with seams (issue 8), written as
   DIR/quality.json: max_seam_gap_m (widest gap of the sewn pairs), particles_inside_body (by the robust
   inside test of the collision module), max_link_strain (largest relative stretch (l - l0)/l0 of a
   stretch link), kinetic_energy_j, sewn_pairs / seam_pairs, wall_s, ranks, fit_maps (per piece: the
   maximum and 95th percentile over its particles of strain, stress_n_per_m and pressure_pa, the fields of
   ClothRunComputeFitMaps), and seam_links (the
   particles of every seam link). -quality_worst N prints the N widest seam pairs and most strained
   particles by piece and grid node. The count of fabric edges
   crossing fabric triangles (fabric_crossings) is added by postprocess/garment_quality.py, which checks
   the XDMF series. */
#pragma once
#include "run.h"

/* Measures the run's final state and writes the JSON file (rank 0). Collective. */
PetscErrorCode ClothRunWriteQuality(ClothRun run, const char path[], PetscReal wall_seconds);
