# Shared by tests/drivers/bend_hysteresis.sh and tests/drivers/shear_hysteresis.sh (sourced; needs CLOTHSIM): the runs of a
# hysteresis scene on 2 ranks, loaded quasi-statically with gravity raised over RAMP seconds, in OUT:
#   full/     the whole run (STEPS steps)
#   elastic/  the same scene with KEY: 0 (no friction)
#   split/    STEPS/2 steps, then restarted from that checkpoint to STEPS; its last checkpoint must be
#             bit-identical to full/'s, the sliders included (tests/checkers/compare_restart.py)
# and hysteresis_refused SCENE SED MESSAGE: the scene edited by SED must be refused with MESSAGE;
# hysteresis_setup_says SCENE SED TEXT: it must run and say TEXT at start-up.
hysteresis_run() { # hysteresis_run DIR SCENE ARGS...
  local dir=$1 sc=$2
  shift 2
  mpiexec -n 2 "$CLOTHSIM" -scene "$sc" -gravity_ramp "$ramp" -ksp_rtol 1e-12 -output_dir "$out/$dir" "$@" > "$out/$dir.log" 2>&1 || { tail -20 "$out/$dir.log"; exit 1; }
}

hysteresis_runs() { # hysteresis_runs OUT SCENE KEY RAMP STEPS
  out=$1 scene=$2 ramp=$4
  local key=$3 steps=$5 half
  half=$(printf "%06d" $(($5 / 2)))
  rm -rf "$out"
  mkdir -p "$out"
  sed "s/^    $key: .*/    $key: 0/" "$scene" > "$out/elastic.yaml"
  hysteresis_run full "$scene"
  hysteresis_run elastic "$out/elastic.yaml"
  hysteresis_run split "$scene" -steps $((steps / 2))
  hysteresis_run split "$scene" -restart "$out/split/checkpoint_$half.h5"
  /usr/bin/python3 tests/checkers/compare_restart.py "$out/full/checkpoint_$(printf "%06d" "$steps").h5" "$out/split/checkpoint_$(printf "%06d" "$steps").h5"
}

hysteresis_refused() { # hysteresis_refused SCENE SED MESSAGE
  sed "$2" "$1" > "$out/refused.yaml"
  if mpiexec -n 1 "$CLOTHSIM" -scene "$out/refused.yaml" -steps 1 -output_dir "$out/refused" > "$out/refused.log" 2>&1; then
    echo "FAIL: accepted: $2"
    exit 1
  fi
  grep -q "$3" "$out/refused.log" || { echo "FAIL: no clear message ($3)"; tail -5 "$out/refused.log"; exit 1; }
}

hysteresis_setup_says() { # hysteresis_setup_says SCENE SED TEXT: the scene edited by SED runs, and its start-up output says TEXT
  sed "$2" "$1" > "$out/edited.yaml"
  mpiexec -n 1 "$CLOTHSIM" -scene "$out/edited.yaml" -steps 1 -output_dir "$out/edited" > "$out/edited.log" 2>&1 || { tail -5 "$out/edited.log"; exit 1; }
  grep -q "$3" "$out/edited.log" || { echo "FAIL: '$2' did not give '$3'"; grep fabric "$out/edited.log"; exit 1; }
}
