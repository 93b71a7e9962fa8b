# Seams and sewing phases (seam.h, sewing.h): closing, bending across the seam, checkpointed state.
clothsim_add_script_test(sewing_two_pieces sewing.sh)
