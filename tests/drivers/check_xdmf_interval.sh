#!/bin/bash
# The .xdmf is rewritten at most every -output_xdmf_seconds (src/output.c), and always at a checkpoint and at the
# end: a run that never reaches the interval must end with the same frame list as one that rewrites it after every
# frame. 9 x 9 sheet, 2 ranks, a frame every step for 12 steps, a checkpoint every 5.
#
#   check_xdmf_interval.sh MPIEXEC DIR
set -euo pipefail
mpiexec=$1 dir=$2
: "${CLOTHSIM:?set CLOTHSIM to the clothsim binary}"
rm -rf "$dir"
mkdir -p "$dir"
for seconds in 0 1000; do
  "$mpiexec" -n 2 "$CLOTHSIM" -scene input/hanging_sheet.yaml -grid 9 -steps 12 -output_every 1 -checkpoint_every 5 \
    -output_xdmf_seconds $seconds -output_dir "$dir/s$seconds" > "$dir/s$seconds.log" 2>&1 || { cat "$dir/s$seconds.log"; echo "FAIL: run with -output_xdmf_seconds $seconds"; exit 1; }
done
/usr/bin/python3 - "$dir" <<'PY'
import sys, xml.etree.ElementTree as ET
d = sys.argv[1]
times = {s: [float(t.get("Value")) for t in ET.parse(f"{d}/s{s}/hanging_sheet.xdmf").getroot().findall(".//Time")] for s in (0, 1000)}
assert len(times[0]) == 13, f"-output_xdmf_seconds 0: {len(times[0])} frames listed, expected 13 (steps 0 to 12)"
assert times[1000] == times[0], f"-output_xdmf_seconds 1000 lists {times[1000]}, every frame lists {times[0]}"
text = {s: [l for l in open(f"{d}/s{s}/hanging_sheet.xdmf") if "run_id" not in l] for s in (0, 1000)}
assert text[0] == text[1000], "the two .xdmf files differ beyond their run_id"
print(f"PASS: both .xdmf files list the same {len(times[0])} frames, t = {times[0][0]} to {times[0][-1]} s")
PY
