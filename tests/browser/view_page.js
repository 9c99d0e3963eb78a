// SPDX-License-Identifier: Apache-2.0
// Drives `lasmesh view` as its user would, in headless Chromium (puppeteer-core), and checks its
// safety from outside the browser (Node's http, which sets any Host header):
// - a request without the token, with a wrong one, or naming another host (DNS rebinding) or
//   port gets 403; a path the server does not serve gets 404;
// - the page loads with the server's mesh and its controls; a new simplify bound typed in and
//   "Mesh" clicked gives a new mesh from the accumulated grid (the server says: no re-read), whose
//   triangle count the page shows; "Save" writes the outputs and shows the command line that
//   writes the same (printed as "command: ..." for the shell to run and compare); another grid
//   reads the points again (the server says so).
// Prints "ok - ..." or "not ok - ..." a check; exits 1 if any failed, 77 if it cannot run here.
//
// Usage: node view_page.js MODULES URL [--screenshot FILE.png] [--chromium PATH]
"use strict";
const http = require("http");
const path = require("path");
const { puppeteerOr77, withChromium, checks, newTab, patience } = require("./chromium.js");

const args = process.argv.slice(2);
const modules = path.resolve(args[0] || "", "node_modules");
const url = new URL(args[1]);
const option = (name, fallback) => (args.includes(name) ? args[args.indexOf(name) + 1] : fallback);
const screenshot = option("--screenshot", null);
const chromium = option("--chromium", "/usr/bin/chromium");
const puppeteer = puppeteerOr77(modules, chromium, "view_page.js");
const tally = checks(), check = tally.check;
const token = url.searchParams.get("token");

// The status of GET `where` sent with the Host header `host`.
const statusOf = (where, host) => new Promise((resolve, reject) => {
  const request = http.request({ host: url.hostname, port: url.port, path: where, headers: { Host: host } }, (r) => {
    r.resume();
    resolve(r.statusCode);
  });
  request.on("error", reject);
  request.end();
});

(async () => {
  const own = `${url.hostname}:${url.port}`;
  const otherPort = `${url.hostname}:${Number(url.port) === 65535 ? 65534 : Number(url.port) + 1}`;
  check("the page with its token: 200", (await statusOf(`/?token=${token}`, own)) === 200);
  check("as localhost: 200", (await statusOf(`/state?token=${token}`, `localhost:${url.port}`)) === 200);
  check("without the token: 403", (await statusOf("/", own)) === 403);
  check("with a wrong token: 403", (await statusOf(`/?token=${"0".repeat(token.length)}`, own)) === 403);
  check("the mesh without the token: 403", (await statusOf("/mesh", own)) === 403);
  check("another host name (DNS rebinding): 403", (await statusOf(`/?token=${token}`, `evil.example:${url.port}`)) === 403);
  check("another port in Host: 403", (await statusOf(`/?token=${token}`, otherPort)) === 403);
  check("a path it does not serve: 404", (await statusOf(`/../../etc/passwd?token=${token}`, own)) === 404);

  await withChromium(puppeteer, chromium, async (browser) => {
    const page = await newTab(browser);
    await page.setViewport({ width: 1400, height: 850 });
    const problems = [];
    page.on("pageerror", (e) => problems.push(String(e)));
    await page.goto(url.href);
    await page.waitForFunction(() => window.lasmesh && (window.lasmesh.ready || window.lasmesh.error), { timeout: patience });
    const first = await page.evaluate(() => ({ error: window.lasmesh.error, triangles: window.lasmesh.triangles,
      live: !!window.lasmesh.live, controls: !document.getElementById("live").hidden,
      simplify: document.getElementById("opt-simplify").value, state: window.lasmesh.live && window.lasmesh.live.state }));
    check("loads without an error", !first.error && problems.length === 0, first.error || problems[0]);
    if (first.error) return;
    check("shows the controls with the command line's options", first.live && first.controls && first.simplify === "0.5cell",
      JSON.stringify(first.simplify));
    check(`shows the server's mesh (${first.triangles} triangles)`, first.triangles === first.state.triangles);

    // Another simplify bound: meshed again from the accumulated grid.
    const mesh = async (settings) => {
      for (const [id, value] of Object.entries(settings)) {
        await page.$eval(`#${id}`, (e) => { e.value = ""; });
        await page.type(`#${id}`, value);
      }
      await page.click("#remesh");
      await page.waitForFunction(() => window.lasmesh.live.job && document.getElementById("remesh").disabled === false,
        { timeout: patience });
      await page.evaluate(() => window.lasmesh.live.job);
      return page.evaluate(() => ({ triangles: window.lasmesh.triangles, reread: window.lasmesh.live.reread,
        state: window.lasmesh.live.state, status: document.getElementById("live-status").textContent,
        shown: document.getElementById("triangles").textContent }));
    };
    const finer = await mesh({ "opt-simplify": "0.2cell" });
    check("a new simplify bound: meshed from the accumulated grid, not read again",
      finer.reread === false && /no re-read/.test(finer.status), `${finer.reread} "${finer.status}"`);
    check(`shows the new mesh (${finer.triangles} triangles, more than ${first.triangles})`,
      finer.triangles === finer.state.triangles && finer.shown === String(finer.triangles) &&
      finer.triangles > first.triangles, JSON.stringify(finer));
    check("the command line names the new bound", / --simplify 0\.2cell/.test(finer.state.command), finer.state.command);
    const refused = await mesh({ "opt-simplify": "fine" });
    check("an option the command line refuses is refused, with its flag, and the mesh stays",
      /--simplify/.test(refused.status) && refused.triangles === finer.triangles, refused.status);
    await page.$eval("#opt-simplify", (e) => { e.value = "0.2cell"; });

    // Save: the outputs the command line named, and the command line that writes the same.
    await page.click("#save");
    await page.waitForFunction(() => window.lasmesh.live.saved || /saved|not one|cannot/.test(
      document.getElementById("live-status").textContent), { timeout: patience });
    await page.evaluate(() => window.lasmesh.live.job);
    const saved = await page.evaluate(() => ({ saved: window.lasmesh.live.saved,
      command: document.getElementById("live-command").textContent }));
    check("Save writes the outputs", saved.saved && saved.saved.written.length >= 1, JSON.stringify(saved));
    if (saved.saved) console.log(`command: ${saved.saved.command}`);
    if (screenshot) await page.screenshot({ path: screenshot });

    // Another grid: the points read again.
    const coarse = await mesh({ "opt-grid": "64" });
    check("another grid: the points read again, and the page says so",
      coarse.reread === true && /read again/.test(coarse.status) && coarse.triangles < finer.triangles,
      `${coarse.reread} "${coarse.status}" ${coarse.triangles}`);
    check("no page error all along", problems.length === 0, problems[0]);
  });
  process.exit(tally.failures ? 1 : 0);
})().catch((e) => {
  console.log(`not ok - view_page.js: ${e && e.stack}`);
  process.exit(1);
});
