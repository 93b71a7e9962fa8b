# The geometry layer and the cell grid shared by body collisions and self-collision (src/geometry.c,
# src/cellgrid.c) against brute force on 2000 seeded random cases each (tests/programs/test_geometry.c): closest
# point on a triangle (degenerate ones included) and of two segments no farther than any of 41^2 sampled
# points (1e-12 m); box queries and segment walks of the grid miss no item; a non-finite or overflowing box
# is an error, a 2e300 m box with 1 mm cells ends with at most the allowed cells.
clothsim_add_test_program(test_geometry test_geometry.c)
clothsim_add_mpi_test(geometry_kernels 1 $<TARGET_FILE:test_geometry>)

# The mesh bodies' inside test (src/winding.c: a bounding-sphere tree with dipole far fields and a bounded error)
# against the exact winding number on the mannequin (tests/programs/test_winding.c): 5,000 random points in its box
# and 5,352 points 1 and 0.1 mm off its surface: every estimate within its error bound of the exact sum, every point
# classified as the exact sum does, and the tree deciding alone for at least 99 % of each set (measured: all). About 6 s.
clothsim_add_test_program(test_winding test_winding.c)
clothsim_add_mpi_test(geometry_winding_tree 1 $<TARGET_FILE:test_winding> -mesh ${CMAKE_SOURCE_DIR}/input/mannequin/makehuman_body.obj -scale 0.1)
