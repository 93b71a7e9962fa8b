#!/bin/bash
# The docs name what the code has:
# 1. every src/*.c and src/*.h is in docs/architecture.md's map (the first column of its "src/" table, where
#    `name.c/.h` stands for name.c and name.h), and every file and folder the map's two tables name exists;
# 2. every option clothsim registers is in docs/options.md, written `-name` followed by a space or a backtick:
#    a. every name the sources register with a PetscOptions*("-name", ...) call (src/*.c; some groups are
#       read only when a scene uses them, and -quality_worst only at the end of a run, so -help cannot show all);
#    b. every option that `$CLOTHSIM -scene SCENE -help` prints in one of clothsim's own option groups (the
#       titles of the PetscOptionsBegin calls in src/*.c), for a garment (bodies, seams, self-collision) and a
#       large sheet (the pattern-grid multigrid).
# Fails with one FAIL line per missing name.
#
#   check_docs_map.sh      (CLOTHSIM: the binary; run from the repository root)
set -euo pipefail
: "${CLOTHSIM:?set CLOTHSIM to the clothsim binary}"
map=docs/architecture.md options=docs/options.md
missing=0
fail() {
  echo "FAIL: $*"
  missing=$((missing + 1))
}
[ -f "$map" ] && [ -f "$options" ] || { echo "FAIL: run from the repository root ($map, $options)"; exit 1; }

# 1. The map: backticked names in the first column of each table row, expanded; src/ rows are files in src/.
map_names=$(awk '/^## /{section=$2} /^\| `/{split($0, cell, "|"); print section "\t" cell[2]}' "$map" |
  while IFS=$'\t' read -r section cell; do
    for name in $(grep -o '`[^`]*`' <<<"$cell" | tr -d '`'); do
      case $name in
        *.c/.h) echo "$section ${name%.c/.h}.c"; echo "$section ${name%.c/.h}.h" ;;
        *) echo "$section $name" ;;
      esac
    done
  done)
[ -n "$map_names" ] || { echo "FAIL: no table rows found in $map"; exit 1; }
src_in_map=$(awk '$1 == "src/" {print $2}' <<<"$map_names" | sort -u)
[ "$(wc -l <<<"$src_in_map")" -ge 20 ] || { echo "FAIL: the map's src/ table names only $(wc -l <<<"$src_in_map") files"; exit 1; }
while read -r section name; do
  if [ "$section" = "src/" ]; then
    [ -e "src/$name" ] || fail "$map names src/$name, which does not exist"
  else
    [ -e "$name" ] || fail "$map names $name, which does not exist"
  fi
done <<<"$map_names"
nsrc=0
for file in src/*.c src/*.h; do
  nsrc=$((nsrc + 1))
  grep -qx -- "${file#src/}" <<<"$src_in_map" || fail "$file is not in $map's map"
done

# 2a. The options the sources register.
registered=$(grep -ho 'PetscOptions[A-Za-z]*("-[a-z][a-z0-9_]*[a-z0-9]"' src/*.c | sed 's/.*("//; s/"$//' | sort -u)
[ "$(wc -l <<<"$registered")" -ge 50 ] || { echo "FAIL: found only $(wc -l <<<"$registered") registered options in src/*.c"; exit 1; }

# 2b. The options -help prints in clothsim's own groups.
titles=$(grep -ho 'PetscOptionsBegin([^,]*, [^,]*, "[^"]*"' src/*.c | sed 's/.*, "//; s/"$//' | sort -u)
[ -n "$titles" ] || { echo "FAIL: no PetscOptionsBegin titles in src/*.c"; exit 1; }
helped=""
for scene in input/dress_fitted_coarse.yaml input/hanging_sheet.yaml; do
  output=$("$CLOTHSIM" -scene "$scene" -help 2>&1) || { tail -5 <<<"$output"; echo "FAIL: $CLOTHSIM -scene $scene -help failed"; exit 1; }
  # A group is its title line and the indented option lines under it, up to the next unindented line.
  group_options=$(awk -v titles="$titles" '
    BEGIN { n = split(titles, t, "\n"); for (i = 1; i <= n; i++) own[t[i] ":"] = 1 }
    /^[^ ]/ { in_own = ($0 in own); next }
    in_own && /^ +-[a-z]/ { sub(/^ +/, ""); sub(/[ :<].*/, ""); print }' <<<"$output")
  [ "$(wc -l <<<"$group_options")" -ge 20 ] || { echo "FAIL: -help of $scene shows only $(wc -l <<<"$group_options") options in clothsim's groups"; exit 1; }
  helped=$(printf '%s\n%s\n' "$helped" "$group_options")
done
helped=$(grep -v '^$' <<<"$helped" | sort -u)

noptions=0
for option in $(printf '%s\n%s\n' "$registered" "$helped" | sort -u); do
  noptions=$((noptions + 1))
  grep -q -- "\`$option[ \`]" "$options" || fail "$option is not in $options"
done

[ "$missing" -eq 0 ] || { echo "FAIL: $missing name(s) missing"; exit 1; }
echo "docs: $nsrc source files in the map, $(wc -l <<<"$map_names") map entries exist, $noptions options in $options"
