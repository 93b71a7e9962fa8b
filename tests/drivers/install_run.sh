#!/bin/bash
# cmake --install into a temporary prefix, then the installed copy on its own, from a directory outside the
# source and build trees: jobs/main_job.sbatch (run with bash, no Slurm) runs the main job's scene
# (input/dress_fitted_coarse.yaml, the mannequin found relative to the installed scene) for 3 steps with the installed binary,
# then the installed postprocess/garment_quality.py (which imports the installed postprocess/fabric_crossings.py;
# nothing from tests/ is installed);
# and the installed postprocess/elastica.py --check.
#
#   install_run.sh MPIEXEC WORKDIR       (CLOTHSIM_BUILD set by ctest)
set -euo pipefail
: "${CLOTHSIM_BUILD:?set CLOTHSIM_BUILD to the build directory}"
mpiexec=$1 work=$2
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$work"
mkdir -p "$work/run"
prefix=$work/prefix
cmake --install "$CLOTHSIM_BUILD" --prefix "$prefix" > "$work/install.log" || { cat "$work/install.log"; fail "cmake --install"; }
share=$prefix/share/clothsim
for f in bin/clothsim share/clothsim/input/dress_fitted_coarse.yaml share/clothsim/input/dress.yaml share/clothsim/input/mannequin/makehuman_body.obj \
         share/clothsim/input/hanging_sheet.yaml share/clothsim/jobs/main_job.sbatch share/clothsim/jobs/clothsim_job.sh \
         share/clothsim/jobs/chain.sh share/clothsim/postprocess/cloth_state.py share/clothsim/postprocess/garment_quality.py \
         share/clothsim/postprocess/elastica.py share/clothsim/postprocess/fabric_crossings.py \
         share/clothsim/postprocess/pvpython_xvfb.sh share/clothsim/postprocess/render.py; do
  [ -e "$prefix/$f" ] || fail "$f not installed"
done
[ ! -e "$share/tests" ] || fail "$share/tests installed: the installed tools must not depend on tests/"
[ -x "$prefix/bin/clothsim" ] && [ -x "$share/jobs/main_job.sbatch" ] || fail "installed programs not executable"
echo "installed $(find "$prefix" -type f | wc -l) files into $prefix"

cd "$work/run"
# CLOTHSIM is not set: the job finds PREFIX/bin/clothsim from CLOTHSIM_ROOT=PREFIX/share/clothsim
# GARMENT_OUTPUTS_CHECK=1: the pictures' commands of jobs/garment_outputs.sh (shared with scripts/run_main.sh) are
# parsed by render.py's and movie.py's own parsers instead of run (7 stills and the movie: minutes of pvpython)
env -u CLOTHSIM CLOTHSIM_ROOT="$share" MPIEXEC="$mpiexec" RANKS=1 STEPS=3 RENDER=1 GARMENT_OUTPUTS_CHECK=1 PYTHON=/usr/bin/python3 \
  OUTPUT_DIR=dress bash "$share/jobs/main_job.sbatch" > job.log 2>&1 || { cat job.log; fail "main_job.sbatch from the installed copy"; }
grep -q -- "$prefix/bin/clothsim -scene input/dress_fitted_coarse.yaml" job.log || { cat job.log; fail "the job did not run the installed binary on input/dress_fitted_coarse.yaml"; }
grep -q "run done: .*checkpoint_000003.h5 is at step 3 of 3" job.log || { cat job.log; fail "the run did not reach step 3"; }
[ -f dress/dress_fitted_coarse.xdmf ] && [ -f dress/quality.json ] || fail "no output in $work/run/dress (OUTPUT_DIR relative to the submit directory)"
grep -q "fabric crossings counted in frame 000003" job.log || { cat job.log; fail "the installed garment_quality.py did not run"; }
renders=$(grep -c "^garment_outputs: render .*dress/dress_fitted_coarse.xdmf --frame -1 --view \(front\|side\|back\) --color-by \(fabric\|strain\|pressure\)" job.log)
[ "$renders" = 7 ] || { cat job.log; fail "main_job.sbatch asked for $renders renders, expected 7 (3 views shaded as cloth, strain and pressure front and back)"; }
grep -q "^garment_outputs: movie .*dress/dress_fitted_coarse.xdmf --out .*dress/dress_fitted_coarse.mp4" job.log || { cat job.log; fail "main_job.sbatch did not ask for the movie"; }
! grep -q "do not parse" job.log || { cat job.log; fail "a picture command of main_job.sbatch does not parse"; }
[ ! -e "$share/dress" ] && [ ! -e "$share/output" ] || fail "the job wrote into the installed tree"
# the binary alone, the scene given by its absolute path: the mannequin is found next to the installed scene
"$mpiexec" -n 1 "$prefix/bin/clothsim" -scene "$share/input/dress_fitted_coarse.yaml" -steps 1 -output_dir direct > direct.log 2>&1 \
  || { cat direct.log; fail "the installed binary on the installed dress scene, from $work/run"; }
grep -q "checkpoint direct/checkpoint_000001.h5" direct.log || { cat direct.log; fail "no checkpoint from the direct run"; }
/usr/bin/python3 "$share/postprocess/elastica.py" --check > elastica.log || { cat elastica.log; fail "installed elastica.py --check"; }
echo "installed copy: the main job's scene ran 3 steps from $work/run, garment_quality.py and elastica.py ran, the 8 picture commands parse"
