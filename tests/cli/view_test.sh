#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# `lasmesh view`: started on a small deck, driven in headless Chromium (tests/browser/view_page.js):
# token and Host checks, a new mesh from the accumulated grid without a re-read (the server's log
# says so), Save, and the command line it shows writes the same bytes; another grid reads again.
# With --refine-thin (driven through the page's own requests): the thin parts re-used for a new
# bound, read again for a new iso, and Save's bytes the command line's.
# Ends with SIGTERM: exit 143, no output half-written.
# LASMESH_SCREENSHOTS=FOLDER keeps a picture of the page (docs/img/view-page.png comes from here).
# Skipped (77) where Chromium or puppeteer-core is not installed (tools/test.sh installs them).
# Usage: view_test.sh LASMESH LASGEN BROWSER_PACKAGES_FOLDER
set -u
lasmesh=$1 lasgen=$2 packages=$3 here=$(cd "$(dirname "$0")" && pwd)
source "$here/common.sh"
cd "$dir" # the names as a user types them: the command line shown is then theirs

"$lasgen" --scene deck --points 300000 --epsg 32631 -o "$dir/deck.las" > /dev/null
"$lasmesh" view deck.las -o deck.ply -o deck.html > "$dir/url.txt" 2> "$dir/log.txt" &
server=$!
trap 'kill $server 2>/dev/null; chmod -R u+w "$dir"; rm -rf "$dir"' EXIT
for _ in $(seq 3000); do # up to 5 minutes: it meshes first (sanitized, on a slow machine, slowly)
  [ -s "$dir/url.txt" ] || ! kill -0 $server 2>/dev/null && break
  sleep 0.1
done
url=$(head -1 "$dir/url.txt")
check "prints a URL on 127.0.0.1 with a token" grep -Eq '^http://127\.0\.0\.1:[0-9]+/\?token=[0-9a-f]{32}$' "$dir/url.txt"
check "nothing written before Save" test ! -e "$dir/deck.ply"

shot=()
[ -n "${LASMESH_SCREENSHOTS:-}" ] && shot=(--screenshot "$LASMESH_SCREENSHOTS/view-page.png")
node "$here/../browser/view_page.js" "$packages" "$url" "${shot[@]}" > "$dir/page.txt"; rc=$?
cat "$dir/page.txt"
[ "$rc" -eq 77 ] && exit 77
check "in Chromium: every check passes" test "$rc" -eq 0
check "the server says the new bound re-used the grid" has "$dir/log.txt" "from the accumulated grid (no re-read)"
check "the server says the new grid read the points again" has "$dir/log.txt" "the inputs read again for the grid"

# The command line the page showed, run: the same bytes as Save wrote.
command=$(sed -n 's/^command: //p' "$dir/page.txt")
check "the page showed a command line" test -n "$command"
mkdir -p "$dir/saved" && cp "$dir/deck.ply" "$dir/deck.html" "$dir/saved/" 2>/dev/null
PATH="$(dirname "$lasmesh"):$PATH" bash -c "$command -q" 2> "$dir/command.txt"
check "the command line runs" test -s "$dir/deck.ply"
check "its PLY is Save's, byte for byte" cmp -s "$dir/deck.ply" "$dir/saved/deck.ply"
check "its page is Save's, byte for byte" cmp -s "$dir/deck.html" "$dir/saved/deck.html"

kill -TERM $server; wait $server; rc=$?
check "SIGTERM stops it (exit 143)" test "$rc" -eq 143
check "no temporary file left" bash -c "! ls -a '$dir' | grep -q '\\.tmp'"

# With --refine-thin: a new bound re-uses the thin parts read for the first mesh; a new iso reads
# them again (the log says which); Save writes the command line's bytes.
"$lasmesh" view deck.las --refine-thin -o thin.ply > "$dir/url2.txt" 2> "$dir/log2.txt" &
server=$!
for _ in $(seq 3000); do
  [ -s "$dir/url2.txt" ] || ! kill -0 $server 2>/dev/null && break
  sleep 0.1
done
node -e '
const [url, ...bodies] = process.argv.slice(1);
(async () => {
  for (const body of bodies) {
    const [path, json] = body.split(" ");
    const u = new URL(url); u.pathname = path;
    const answer = await (await fetch(u, { method: "POST", body: json })).json();
    if (answer.error) throw new Error(answer.error);
    if (answer.command) console.log(`command: ${answer.command}`);
  }
})().catch((e) => { console.log(`error: ${e.message}`); process.exit(1); });' "$(head -1 "$dir/url2.txt")" \
  '/mesh {"simplify":"0.25cell"}' '/mesh {"iso":"3"}' '/save {"outputs":["thin.ply"]}' > "$dir/thin-api.txt"; rc=$?
check "--refine-thin: the page's new bound, iso and Save answered (rc $rc: $(head -c 300 "$dir/thin-api.txt"))" test "$rc" -eq 0
check "--refine-thin: a new bound re-uses the thin parts" grep -q "from the accumulated grid (no re-read): .*--simplify 0.25cell" "$dir/log2.txt"
check "--refine-thin: a new iso reads them again" grep -q "the inputs read again for the thin parts at this iso: .*--iso 3" "$dir/log2.txt"
command=$(sed -n 's/^command: //p' "$dir/thin-api.txt")
mv thin.ply saved/thin.ply 2> /dev/null
PATH="$(dirname "$lasmesh"):$PATH" bash -c "$command -q" 2> "$dir/command.txt"
check "--refine-thin: Save's PLY is its command line's ($command), byte for byte" cmp -s thin.ply saved/thin.ply
kill -TERM $server; wait $server
finish view
