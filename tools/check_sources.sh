#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Checks on the sources that no compiler makes (tools/test.sh runs it first):
#  - formatted as .clang-format says (tools/format.sh --check);
#  - the library speaks no command-line flag: errors and notes in src/ outside src/cli/ say what
#    happened in words and name the option through Error::option, and the command line adds its
#    flag, so a library user never gets advice about flags they do not have;
#  - every source file carries its SPDX licence line;
#  - every file of code in src/ and kernels/ has a named mutation (tools/mutations.tsv), so
#    tools/mutate.sh can show that some test fails when it is wrong, and each mutation's
#    original text stands once in its file.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/format.sh --check
flags=$(git ls-files 'src/*' ':!src/cli/*' | xargs grep -nE -- '--[a-z][a-z]+(-[a-z]+)*' |
  grep -vE -- '--(level|depth|pieces|size_|i|j|k|n|count|left)\b' || true)
if [ -n "$flags" ]; then
  echo "sources: command-line flags in the library (src/ outside src/cli/):" >&2
  echo "$flags" >&2
  exit 1
fi
unlicensed=$(git ls-files 'src/*' 'include/*' 'tests/*.cpp' 'tests/*.hpp' 'tests/cli/*.sh' 'tools/*.sh' 'tools/*.cpp' \
  'tools/*.hpp' 'kernels/*' | xargs grep -L 'SPDX-License-Identifier' || true)
if [ -n "$unlicensed" ]; then
  echo "sources: no SPDX-License-Identifier line in: $unlicensed" >&2
  exit 1
fi
mutated=$(cut -f2 tools/mutations.tsv | sort -u)
unmutated=$(git ls-files 'src/*.cpp' 'src/*.js' 'kernels/*.cl' | while read -r f; do
  grep -qxF "$f" <<< "$mutated" || echo "$f"
done)
if [ -n "$unmutated" ]; then
  echo "sources: no mutation in tools/mutations.tsv for: $unmutated" >&2
  exit 1
fi
# A mutation whose original text no longer stands once in its file (reformatted, renamed) would
# only show up as "invalid" when tools/mutate.sh draws it.
stale=$(grep -v '^#' tools/mutations.tsv | while IFS=$'\t' read -r name file _ original _; do
  [ -n "$name" ] || continue
  [ "$(grep -cF -- "$original" "$file" 2> /dev/null)" = 1 ] || echo "$name ($file)"
done)
if [ -n "$stale" ]; then
  echo "sources: mutations whose original text is not in their file exactly once: $stale" >&2
  exit 1
fi
echo "sources: no command-line flags in the library; every source file has its licence line; every file of code a mutation, each"
echo "         mutation's original text once in its file"
