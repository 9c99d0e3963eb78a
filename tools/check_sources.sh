#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Checks on the sources that no compiler makes (tools/test.sh runs it first):
#  - formatted as .clang-format says (tools/format.sh --check);
#  - the library speaks no command-line flag: errors and notes in src/ outside src/cli/ say what
#    happened in words and name the option through Error::option, and the command line adds its
#    flag, so a library user never gets advice about flags they do not have;
#  - every source file carries its SPDX licence line;
#  - every file of code in src/ and kernels/ has a named mutation (tools/mutations.tsv), so
#    tools/mutate.sh can show that some test fails when it is wrong.
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
echo "sources: no command-line flags in the library; every source file has its licence line; every file of code a mutation"
