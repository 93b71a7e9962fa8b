/* The private part of the Scene reader, shared by its files: src/scene.c (create, parse, the document's blocks in
   order, cross-checks, -grid, view, destroy), src/scene_schema.c (the allowed keys of every block, the bounds of
   its reals, the defaults), src/scene_fabric.c (the fabrics: block), src/scene_piece.c (the pieces: list),
   src/scene_blocks.c (run:, bodies:, self_collision:, seams:, sewing:) and src/scene_file.c (the file's bytes read
   on rank 0 and broadcast). The generic YAML reader they all use is src/scene_reader.h. */
#pragma once
#include "scene.h"
#include "scene_reader.h"

#define SCENE_ORTHOGONALITY_TOL 1e-6  /* |u.v| of unit axes that count as orthogonal (and parallel: 1 - it) */
#define SCENE_CORNER_JOIN_RTOL 1e-6   /* boundary ends this fraction of the outline's size apart still meet: coordinates typed with 7 digits join */
#define SCENE_PLANE_DISTANCE_TOL 1e-6 /* m: a point this close to a piece's plane lies in it (a cone's apex; not a cylinder's axis point) */
/* The most particles a scene may have: the state vectors hold 3 coordinates per particle, indexed by PetscInt
   (32 bits in Debian's PETSc). Sizes are multiplied in 64 bits, so that a grid beyond it is named, not wrapped. */
#define SCENE_MAX_PARTICLES ((PetscInt64)PETSC_MAX_INT / 3)
/* The largest extent of a piece, m (size, and the coordinates of an outline): a kilometre is a unit mistake. */
#define SCENE_MAX_PIECE_EXTENT 1e3
/* The most segments of an arc boundary: its points are allocated before anything else (segments: 2147483647 ended in
   the allocator); 100,000 segments put a vertex every 0.06 mm of a 1 m circle, far finer than any grid. */
#define SCENE_MAX_ARC_SEGMENTS 100000

/* scene_schema.c: the allowed keys of each block (NULL-terminated), checked before any of its values is read. */
extern const char *const SceneIntegrators[];
extern const char *const SceneTopKeys[];
extern const char *const SceneFabricKeys[];
extern const char *const SceneKESKeys[];
extern const char *const ScenePieceKeys[];
extern const char *const SceneWrapKeys[];
extern const char *const SceneBoundaryKeys[];
extern const char *const SceneArcKeys[];
extern const char *const ScenePinDiscKeys[];
extern const char *const ScenePinBoxKeys[];
extern const char *const SceneRunKeys[];
extern const char *const SceneBodyKeys[];
extern const char *const SceneBodyTypeKeys[][5];
extern const char *const SceneFrictionKeys[];
extern const char *const SceneSelfCollisionKeys[];
extern const char *const SceneSeamKeys[];
extern const char *const SceneSeamSideKeys[];
extern const char *const SceneSewingKeys[];
/* The upper (and some lower) bounds of real keys, ended by a NULL key (SceneReader.bounds). */
extern const SceneRealBound SceneRealBounds[];

/* scene_schema.c: the defaults that are not zero, each set before its block or item is read (a key that is absent
   keeps it). The scene's: its path and its name from the path, gravity, the sewing block's. */
PetscErrorCode SceneSetDefaults(Scene scene, const char path[]);
PetscErrorCode SceneFabricSetDefaults(SceneFabric *fabric);
PetscErrorCode ScenePieceSetDefaults(ScenePiece *piece);
/* index: the body's place in the list, which names it when the scene does not. */
PetscErrorCode SceneBodySetDefaults(SceneBody *body, PetscInt index);
PetscErrorCode SceneSelfCollisionSetDefaults(SceneSelfCollision *self);
/* index: the seam's place in the list, which names it when the scene does not. */
PetscErrorCode SceneSeamSetDefaults(SceneSeam *seam, PetscInt index);

/* The readers of the top-level blocks, in the order SceneReadDocument (scene.c) calls them; each reads root[its key]. */
PetscErrorCode SceneReadFabrics(SceneReader *r, yaml_node_t *root, Scene scene);       /* scene_fabric.c */
PetscErrorCode SceneReadPieces(SceneReader *r, yaml_node_t *root, Scene scene);        /* scene_piece.c, after the fabrics */
PetscErrorCode SceneReadRun(SceneReader *r, yaml_node_t *root, SceneRunDefaults *run); /* scene_blocks.c, the rest */
PetscErrorCode SceneReadBodies(SceneReader *r, yaml_node_t *root, Scene scene);
PetscErrorCode SceneReadSelfCollision(SceneReader *r, yaml_node_t *root, Scene scene); /* after the pieces */
PetscErrorCode SceneReadSeams(SceneReader *r, yaml_node_t *root, Scene scene);         /* after the pieces */
PetscErrorCode SceneReadSewing(SceneReader *r, yaml_node_t *root, SceneSewing *sewing);

/* scene.c: errors when the pieces have more than SCENE_MAX_PARTICLES particles in all; cause says what set the grids
   ("" for the file, "-grid N"). */
PetscErrorCode SceneCheckParticleCount(Scene scene, const char cause[]);
/* scene_piece.c: the largest distance between neighbouring particles of a piece in its flat layout, m. */
PetscReal ScenePieceLargestSpacing(const ScenePiece *piece);
/* scene_piece.c: resolves pins_given (negative: from the end) into pins for the piece's current grid. */
PetscErrorCode ScenePieceResolvePins(MPI_Comm comm, const char path[], ScenePiece *piece);

/* scene_file.c: collective: every rank gets the file's bytes (NUL-terminated) from rank 0. */
PetscErrorCode SceneReadBytes(MPI_Comm comm, const char path[], char **bytes, size_t *len);
