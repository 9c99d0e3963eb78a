#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Mutation testing: does the test suite notice when central code is wrong? Each named mutation in
# tools/mutations.tsv changes one line of src/ or kernels/ (a dropped term, an off-by-one, a
# swapped sign), in a copy of the tree built on its own (build-mutate/); the tests named for it
# then run, and the mutation is caught when one of them fails (or hangs past 10 minutes), missed
# when all pass, invalid when it does not compile. The unmutated copy must pass those tests first.
#
# Usage: bash tools/mutate.sh [NAME...]          the named mutations, or all of them
#        bash tools/mutate.sh --random N [--seed S]   N mutations drawn at random
#        bash tools/mutate.sh --list              the names, files and tests
# Results: a line per mutation, the score, and build-mutate/results.tsv. tools/build.sh and
# tools/test.sh first (the glTF validator and laz-perf the tests use come from build/).
# mutations.tsv: NAME <tab> FILE <tab> TESTS <tab> ORIGINAL <tab> REPLACEMENT, where ORIGINAL occurs
# exactly once in FILE and TESTS are `unit:PATTERN` (lasmesh_tests -tc=PATTERN) or `ctest:REGEX`.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
list=${MUTATIONS:-tools/mutations.tsv}
work=$root/build-mutate
tree=$work/tree
build=$tree/build

random=0 seed=1 names=()
while [ $# -gt 0 ]; do
  case $1 in
    --list) grep -v '^#' "$list" | awk -F'\t' 'NF == 5 {printf "%-34s %-40s %s\n", $1, $2, $3}'; exit 0 ;;
    --random) random=$2; shift 2 ;;
    --seed) seed=$2; shift 2 ;;
    -*) echo "mutate: unknown option $1" >&2; exit 1 ;;
    *) names+=("$1"); shift ;;
  esac
done

# The mutations to run, as line numbers of the list.
mapfile -t all < <(grep -n -v '^#' "$list" | awk -F'\t' 'NF == 5 {split($1, a, ":"); print a[1]}')
chosen=()
if [ ${#names[@]} -gt 0 ]; then
  for name in "${names[@]}"; do
    line=$(awk -F'\t' -v n="$name" '$1 == n {print NR}' "$list")
    [ -n "$line" ] || { echo "mutate: no mutation named $name (see --list)" >&2; exit 1; }
    chosen+=("$line")
  done
elif [ "$random" -gt 0 ]; then
  mapfile -t chosen < <(printf '%s\n' "${all[@]}" | shuf -n "$random" --random-source=<(yes "$seed"))
else
  chosen=("${all[@]}")
fi
field() { sed -n "${1}p" "$list" | cut -f"$2"; }
# The test selectors of list line $1, one a line (a unit: pattern may hold spaces).
selectors() { python3 -c 'import re, sys; print("\n".join(re.split(r"\s+(?=(?:unit|ctest):)", sys.argv[1].strip())))' "$(field "$1" 3)"; }

# A copy of the tree (what git tracks or would track), built once without a unity build so that a
# mutation recompiles one file.
mkdir -p "$tree"
# Only files whose content differs are copied, with a fresh time, so the build sees every change
# (tar would restore the source's older times) and a run stopped mid-mutation heals itself.
git ls-files -z -co --exclude-standard | while IFS= read -r -d '' f; do
  [ -f "$f" ] || continue
  cmp -s "$f" "$tree/$f" || { mkdir -p "$tree/$(dirname "$f")"; cp "$f" "$tree/$f"; }
done
mkdir -p "$build"
for tool in gltf-validator laz-perf browser 3d-tiles-validator viewer; do ln -sfn "$root/build/$tool" "$build/$tool"; done
[ -d "$root/../shared" ] && export LASMESH_SHARED=${LASMESH_SHARED:-$root/../shared}
if [ ! -f "$build/CMakeCache.txt" ]; then
  cmake -S "$tree" -B "$build" -DCMAKE_BUILD_TYPE=Release > /dev/null
fi
build_tree() { cmake --build "$build" --parallel "$(nproc)" --target lasmesh lasmesh_tests lasgen man_page -- --no-print-directory > "$work/build.log" 2>&1; }
echo "mutate: building the copy in $build" >&2
build_tree || { tail -20 "$work/build.log"; echo "mutate: the unmutated copy does not build" >&2; exit 1; }

# run_tests SELECTORS...: 0 when every selected test passes, 1 when one fails, 3 when one was
# skipped (what it needs is not here: it proves nothing either way).
run_tests() {
  local selector ok=0
  for selector in "$@"; do
    case $selector in
      unit:*) timeout 600 "$build/lasmesh_tests" -tc="${selector#unit:}" > "$work/test.log" 2>&1 || ok=1 ;;
      ctest:*)
        (cd "$build" && timeout 900 ctest -R "${selector#ctest:}" --timeout 600 > "$work/test.log" 2>&1) || ok=1
        [ "$ok" -eq 0 ] && grep -q "Skipped\|Not Run" "$work/test.log" && return 3 ;;
      *) echo "mutate: unknown test selector $selector" >&2; return 2 ;;
    esac
    [ "$ok" -eq 0 ] || return 1
  done
}

# The tests chosen mutations name must pass on the unmutated copy.
mapfile -t baseline < <(for line in "${chosen[@]}"; do selectors "$line"; done | sort -u)
echo "mutate: ${#baseline[@]} test selections on the unmutated copy" >&2
for selector in "${baseline[@]}"; do
  run_tests "$selector" || { rc=$?; tail -30 "$work/test.log"; echo "mutate: $selector $([ "$rc" -eq 3 ] && echo "is skipped here" || echo "fails") without any mutation" >&2; exit 1; }
done

caught=0 missed=0 invalid=0
: > "$work/results.tsv"
for line in "${chosen[@]}"; do
  name=$(field "$line" 1) file=$(field "$line" 2) tests=$(field "$line" 3)
  original=$(field "$line" 4) replacement=$(field "$line" 5)
  start=$SECONDS
  cp "$root/$file" "$tree/$file"
  if ! python3 - "$tree/$file" "$original" "$replacement" <<'EOF'
import sys
path, original, replacement = sys.argv[1:]
text = open(path).read()
if text.count(original) != 1:
    sys.exit(f"{original!r} occurs {text.count(original)} times in {path}, not once")
open(path, "w").write(text.replace(original, replacement))
EOF
  then
    result=invalid
  elif ! build_tree; then
    result=invalid
  else
    mapfile -t chosen_tests < <(selectors "$line")
    run_tests "${chosen_tests[@]}" && rc=0 || rc=$?
    case $rc in 0) result=missed ;; 3) result=invalid ;; *) result=caught ;; esac
  fi
  cp "$root/$file" "$tree/$file"
  case $result in caught) caught=$((caught + 1)) ;; missed) missed=$((missed + 1)) ;; *) invalid=$((invalid + 1)) ;; esac
  printf '%-7s %-34s %-40s %4ds\n' "$result" "$name" "$file" $((SECONDS - start))
  printf '%s\t%s\t%s\t%s\n' "$result" "$name" "$file" "$tests" >> "$work/results.tsv"
done
build_tree || true # leave the copy unmutated
valid=$((caught + missed))
echo "mutate: $caught of $valid caught ($((valid ? 100 * caught / valid : 0))%), $missed missed, $invalid invalid"
[ "$missed" -eq 0 ] && [ "$invalid" -eq 0 ]
