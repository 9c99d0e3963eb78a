#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# `-o deck.html`: a page that opens offline in headless Chromium (tests/browser/html_page.js)
# and shows, measures and colours what the PLY of the same run holds; the same run writes the same
# bytes; the page around the mesh stays under 800 kB.
# LASMESH_SCREENSHOTS=FOLDER keeps a picture of the page (docs/img/html-page.png comes from here).
# Skipped (77) where Chromium or puppeteer-core is not installed (tools/test.sh installs them).
# Usage: html_test.sh LASMESH LASGEN BROWSER_PACKAGES_FOLDER
set -u
lasmesh=$1 lasgen=$2 packages=$3 here=$(dirname "$0")
source "$here/common.sh"

"$lasgen" --scene deck --points 300000 --epsg 32631 -o "$dir/deck.las" > /dev/null
"$lasmesh" "$dir/deck.las" -o "$dir/deck.html" -o "$dir/deck.ply" > "$dir/summary.txt" 2>&1
check "a page is written" test -s "$dir/deck.html"
check "the summary names it" has "$dir/summary.txt" "deck.html"
"$lasmesh" "$dir/deck.las" -o "$dir/again.html" -q
check "the same run writes the same bytes" cmp -s "$dir/deck.html" "$dir/again.html"
check "the page without its mesh is under 800 kB" python3 -c '
import re, sys
page = open(sys.argv[1]).read()
mesh = re.search(r"id=\"lasmesh-mesh\">([^<]*)<", page).group(1)
assert len(page) - len(mesh) <= 800_000, len(page) - len(mesh)' "$dir/deck.html"

python3 "$here/../browser/ply_facts.py" "$dir/deck.ply" > "$dir/expected.json"
shot=()
[ -n "${LASMESH_SCREENSHOTS:-}" ] && shot=(--screenshot "$LASMESH_SCREENSHOTS/html-page.png")
node "$here/../browser/html_page.js" "$packages" "$dir/deck.html" "$dir/expected.json" "${shot[@]}" > "$dir/page.txt"; rc=$?
cat "$dir/page.txt"
[ "$rc" -eq 77 ] && exit 77
check "in Chromium: every check passes" test "$rc" -eq 0
check "in Chromium: the measurement was checked" grep -q "^ok - the distance is theirs to 1 mm" "$dir/page.txt"

# A heat map as a page (lasmesh compare): the mesh's colours, and on request the distances, whose
# colours are those of the heat-map PLY of the same comparison.
"$lasmesh" compare "$dir/deck.ply" "$dir/deck.las" --heatmap "$dir/heat.ply" --heatmap-scale 0.3 > /dev/null 2>&1
"$lasmesh" compare "$dir/deck.ply" "$dir/deck.las" --heatmap "$dir/heat.html" --heatmap-scale 0.3 > "$dir/compare.txt" 2>&1
check "compare writes the heat map page" has "$dir/compare.txt" "heat.html"
python3 "$here/../browser/ply_facts.py" "$dir/heat.ply" > "$dir/heat.json"
node "$here/../browser/html_page.js" "$packages" "$dir/heat.html" "$dir/expected.json" --heat "$dir/heat.json" > "$dir/heat.txt"; rc=$?
cat "$dir/heat.txt"
check "heat map page in Chromium: every check passes" test "$rc" -eq 0
check "heat map page: the heat colours were checked" grep -q "^ok - the heat map, from above" "$dir/heat.txt"

finish html
