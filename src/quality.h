/* Quality of an assembled garment, measured at the end of a run with seams (issue 8), written as
   DIR/quality.json: max_seam_gap_m (widest gap of the sewn pairs), particles_inside_body (by the robust
   inside test of the collision module), max_link_strain (largest relative stretch (l - l0)/l0 of a
   stretch link), kinetic_energy_j, sewn_pairs / seam_pairs, wall_s, ranks, run_id, fit_maps (per piece: the
   maximum and 95th percentile over its particles of strain, stress_n_per_m and pressure_pa, the fields of
   ClothRunComputeFitMaps), and seam_links (the
   particles of every seam link). -quality_worst N prints the N widest seam pairs and most strained
   particles by piece and grid node. The count of fabric edges
   crossing fabric triangles (fabric_crossings) is added by postprocess/garment_quality.py, which checks
   the XDMF series. */
#pragma once
#include <stdint.h>
#include "cloth.h"
#include "collision.h"
#include "sewing.h"

/* Measures the final state of cloth (with the bodies of collision and the seams of sewing; either may be NULL)
   and writes the JSON file (rank 0), with run_id, the identity of the run (0: none), as 16 hex digits, and the
   summary of the fit maps (natural Vecs of strain, stress and pressure, as ClothRunComputeFitMaps gives them;
   NULL: none). Collective. */
PetscErrorCode ClothQualityWrite(Cloth cloth, ClothCollision collision, ClothSewing sewing, Vec fit_maps[3], uint64_t run_id, const char path[], PetscReal wall_seconds);
