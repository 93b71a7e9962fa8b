# The geometry layer and the cell grid shared by body collisions and self-collision (src/geometry.c,
# src/cellgrid.c) against brute force on 2000 seeded random cases each (tests/programs/test_geometry.c): closest
# point on a triangle (degenerate ones included) and of two segments no farther than any of 41^2 sampled
# points (1e-12 m); box queries and segment walks of the grid miss no item; a non-finite or overflowing box
# is an error, a 2e300 m box with 1 mm cells ends with at most the allowed cells.
clothsim_add_test_program(test_geometry test_geometry.c)
clothsim_add_mpi_test(geometry_kernels 1 $<TARGET_FILE:test_geometry>)
