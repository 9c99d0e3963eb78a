// SPDX-License-Identifier: Apache-2.0
// Opens a lasmesh .html page from file:// in headless Chromium (puppeteer-core) with the network
// cut, and checks what its reader would see: it opens without an error and without asking for
// anything, shows the file's triangle count, draws the mesh, measures between two vertices
// clicked on the screen to a millimetre of their distance in the file, and seen from above in
// flat colours averages the mesh's own colours (the topmost surface's over a plan lattice, as
// ply_facts.py gives them; the pixels inside the drawn mesh, not those blended with the background
// at its outline and holes) to within 3/255; with a heat map, the heat-map PLY's colours the same
// way (5/255); while the camera moves, it draws lighter copies of the mesh where the whole one is
// too slow, and the whole mesh once still.
// Prints "ok - ..." or "not ok - ..." a check; exits 1 if any failed, 77 if it cannot run here.
//
// Usage: node html_page.js MODULES PAGE.html EXPECTED.json [--screenshot FILE.png] [--heat HEAT.json]
//          [--chromium PATH]
// EXPECTED.json: {"triangles": N, "vertices": [[x, y, z], ...] (file coordinates),
//                 "candidates": [vertex numbers to click, best first], "plan_colour": [r, g, b]}
"use strict";
const fs = require("fs");
const path = require("path");
const { puppeteerOr77, withChromium, checks, newTab, patience } = require("./chromium.js");

const args = process.argv.slice(2);
const modules = path.resolve(args[0] || "", "node_modules");
const pageFile = path.resolve(args[1] || "");
const expected = JSON.parse(fs.readFileSync(args[2], "utf8"));
const option = (name, fallback) => (args.includes(name) ? args[args.indexOf(name) + 1] : fallback);
const screenshot = option("--screenshot", null);
// With a heat map: the plan colour of the heat-map PLY of the same comparison (ply_facts.py).
const heat = option("--heat", null) && JSON.parse(fs.readFileSync(option("--heat", null), "utf8"));
const chromium = option("--chromium", "/usr/bin/chromium");
const puppeteer = puppeteerOr77(modules, chromium, "html_page.js");
const tally = checks(), check = tally.check;

(async () => {
  await withChromium(puppeteer, chromium, async (browser) => {
    const page = await newTab(browser);
    await page.setViewport({ width: 1200, height: 800 });
    const asked = [], problems = [];
    await page.setRequestInterception(true);
    page.on("request", (r) => {
      const url = r.url();
      if (url === `file://${pageFile}` || url.startsWith("data:") || url.startsWith("blob:")) return r.continue();
      asked.push(url);
      r.abort();
    });
    page.on("pageerror", (e) => problems.push(String(e)));
    await page.setOfflineMode(true);
    await page.goto(`file://${pageFile}`);
    await page.waitForFunction(() => window.lasmesh && (window.lasmesh.ready || window.lasmesh.error), { timeout: patience });
    const state = await page.evaluate(() => ({ error: window.lasmesh.error, triangles: window.lasmesh.triangles,
      shown: document.getElementById("triangles").textContent }));
    check("opens from file:// offline without an error", !state.error && problems.length === 0, state.error || problems[0]);
    check("asks for nothing outside the page", asked.length === 0, asked.slice(0, 3).join(" "));
    if (state.error) return;
    check(`shows the file's ${expected.triangles} triangles`, state.triangles === expected.triangles &&
      state.shown === String(expected.triangles), `${state.triangles}, shown ${state.shown}`);
    // What is drawn: the share of the frame off the page's background, and its mean colour.
    await page.addScriptTag({ content: fs.readFileSync(path.join(__dirname, "frame_pixels.js"), "utf8") });
    const frame = () => page.evaluate(() => framePixels(window.lasmesh.canvas, "#dde4ea", 6));
    const drawn = await frame();
    check(`draws the mesh (${(100 * drawn.covered).toFixed(1)}% of the frame)`, drawn.covered > 0.05, drawn.covered);

    // Measuring: two far-apart vertices clicked where they are on the screen.
    await page.click("#measure");
    const panel = await page.evaluate(() => document.getElementById("panel").getBoundingClientRect().toJSON());
    const onScreen = [];
    for (const v of expected.candidates) {
      const [x, y] = await page.evaluate((p) => window.lasmesh.screenOfFile(p), expected.vertices[v]);
      const underPanel = x < panel.right + 4 && y < panel.bottom + 4;
      if (x > 4 && y > 4 && x < 1196 && y < 796 && !underPanel) onScreen.push({ v, x, y });
    }
    // A click on a vertex seen edge-on may miss the surface: the next candidate then.
    const clickOne = async (choices) => {
      for (const c of choices) {
        const before = await page.evaluate(() => window.lasmesh.picked().length);
        await page.mouse.click(Math.round(c.x), Math.round(c.y));
        if ((await page.evaluate(() => window.lasmesh.picked().length)) > before) return c;
      }
      return null;
    };
    const a = await clickOne(onScreen);
    const far = a ? onScreen.filter((c) => c !== a).sort((p, q) => Math.hypot(q.x - a.x, q.y - a.y) - Math.hypot(p.x - a.x, p.y - a.y)) : [];
    const b = await clickOne(far);
    if (!a || !b) return check("two vertices to measure between are on the screen", false, onScreen.length);
    const measured = await page.evaluate(() => window.lasmesh.measurement);
    check("measures after two clicks", measured && measured.points.length === 2, JSON.stringify(measured));
    if (measured) {
      const nearest = (p) => {
        let best = Infinity, at = -1;
        expected.vertices.forEach((q, i) => {
          const d = Math.hypot(q[0] - p[0], q[1] - p[1], q[2] - p[2]);
          if (d < best) best = d, at = i;
        });
        return { at, d: best };
      };
      const [na, nb] = measured.points.map(nearest);
      check(`both points are vertices of the file (${(1000 * Math.max(na.d, nb.d)).toFixed(3)} mm away)`, Math.max(na.d, nb.d) < 0.0005,
        `${na.d} ${nb.d}`);
      const [va, vb] = [expected.vertices[na.at], expected.vertices[nb.at]];
      const truth = Math.hypot(va[0] - vb[0], va[1] - vb[1], va[2] - vb[2]);
      check(`the distance is theirs to 1 mm (${measured.distance.toFixed(4)} against ${truth.toFixed(4)})`,
        Math.abs(measured.distance - truth) < 0.001 && truth > 1, measured.distance - truth);
      const text = await page.evaluate(() => document.getElementById("measurement").textContent);
      check("and shows it", text.includes(measured.distance.toFixed(3)), text);
    }
    if (screenshot) await page.screenshot({ path: screenshot }); // with the measurement

    // While the camera moves: lighter copies of the mesh on its vertices, each a quarter of the
    // one before down to at most 1,000 triangles, drawn (at a fraction of the resolution) when the
    // whole mesh is too slow; a quarter second after the last move, the whole mesh again.
    const ways = await page.evaluate(() => window.lasmesh.movingWays());
    const sizes = [...new Set(ways.map((w) => w.triangles))];
    const quartered = sizes.every((n, k) => k === 0 || (n <= (sizes[k - 1] / 4) * 1.5 && n > 0));
    check(`lighter copies for moving: ${sizes.join(", ")} triangles`, sizes[0] === expected.triangles && sizes.length >= 2 &&
      quartered && sizes[sizes.length - 1] <= 1000 && (sizes.length < 3 || sizes[sizes.length - 2] > 1000), JSON.stringify(ways));
    const orbitFrames = (n) => page.evaluate(async (n) => {
      for (let i = 0; i < n; i++) {
        window.lasmesh.orbitBy(0.002);
        await new Promise((r) => requestAnimationFrame(() => r()));
      }
      return { drawn: window.lasmesh.trianglesDrawn(), width: window.lasmesh.canvas.width, moving: window.lasmesh.moving };
    }, n);
    const stillFrame = () => page.evaluate(() => new Promise((r) => setTimeout(() => r({ drawn: window.lasmesh.trianglesDrawn(),
      width: window.lasmesh.canvas.width }), 600)));
    await page.evaluate(() => { window.lasmesh.setFlat(false); window.lasmesh.setMovingBudget(Infinity); });
    const fast = await orbitFrames(12);
    check("a renderer that keeps up draws the whole mesh while moving", fast.drawn === expected.triangles &&
      fast.width === 1200 && fast.moving.triangles === expected.triangles, JSON.stringify(fast));
    await page.evaluate(() => window.lasmesh.setMovingBudget(0)); // every frame too slow
    const slowest = await orbitFrames(8 * ways.length);
    const lightest = ways[ways.length - 1];
    const lightFrame = await frame();
    check(`one that does not steps down to the lightest (${lightest.triangles} triangles at ${lightest.scale} of the resolution, ` +
      `${(100 * lightFrame.covered).toFixed(1)}% of the frame)`, slowest.drawn === lightest.triangles &&
      slowest.width === 1200 * lightest.scale && lightFrame.covered > 0.05, JSON.stringify(slowest));
    const settled = await stillFrame();
    const settledFrame = await frame();
    check("and draws the whole mesh at full resolution once still", settled.drawn === expected.triangles && settled.width === 1200 &&
      settledFrame.covered > 0.05, JSON.stringify(settled));
    const shownMoving = await page.evaluate(() => document.getElementById("moving").textContent);
    check(`says so ("while moving: ${shownMoving}")`, shownMoving.startsWith(lightest.triangles.toLocaleString("en")), shownMoving);
    // The choice alone, from frame intervals (ms) against a 20 ms budget.
    const choices = await page.evaluate(() => [[16, 16, 16, 16, 16], [30, 30, 30, 30, 30], [30, 30, 30], [100, 100, 100, 100],
      [1e4, 1e4, 1e4, 1e4], [16, 500, 16, 16, 16]].map((intervals) => window.lasmesh.wayAfter(intervals, 20)));
    const fits = ways.findIndex((w) => w.triangles <= (expected.triangles * 20) / 100);
    check(`chooses from the frames: keeps up, one step, too few frames, skips to ${fits}, the lightest, one stall ignored ` +
      `(${choices.join(" ")})`, JSON.stringify(choices) === JSON.stringify([0, 1, 0, fits, ways.length - 1, 0]) && fits > 1, choices);

    // A click that turned the camera a pixel or two, while a lighter copy is drawn, picks on the whole mesh.
    await page.evaluate(() => { window.lasmesh.setMovingBudget(Infinity); window.lasmesh.setMovingWay(window.lasmesh.movingWays().length - 1); });
    const target = onScreen.find((c) => c !== a && c !== b) || onScreen[0];
    await orbitFrames(2);
    const [tx, ty] = await page.evaluate((p) => window.lasmesh.screenOfFile(p), expected.vertices[target.v]);
    await page.mouse.move(Math.round(tx) - 2, Math.round(ty));
    await page.mouse.down();
    await page.mouse.move(Math.round(tx), Math.round(ty));
    await page.mouse.up();
    const jittered = await page.evaluate(() => ({ drawn: window.lasmesh.trianglesDrawn(), picked: window.lasmesh.picked().length }));
    check("a click with a little drag while moving picks on the whole mesh", jittered.drawn === expected.triangles, JSON.stringify(jittered));
    await page.evaluate(() => { window.lasmesh.setMovingBudget(20); window.lasmesh.setMovingWay(0); });

    // Colours: from above, flat.
    await page.click("#measure");
    await page.evaluate(() => { window.lasmesh.setFlat(true); window.lasmesh.topView(); });
    const plan = await frame();
    const apart = plan.insideMean.map((m, k) => Math.abs(m - expected.plan_colour[k]));
    check(`from above, in flat colours, the mesh's colours (mean ${plan.insideMean.map((m) => m.toFixed(1)).join(" ")} against ` +
      `${expected.plan_colour.map((m) => m.toFixed(1)).join(" ")})`, Math.max(...apart) <= 3, apart);
    if (heat) {
      const shown = await page.evaluate(() => !document.getElementById("heat-choice").hidden);
      check("offers the heat map", shown);
      await page.click("#heat");
      const legend = await page.evaluate(() => !document.getElementById("heat-legend").hidden);
      check("shows its legend", legend);
      // Within 5/255, not 3: the ramp changes fast between neighbouring vertices, so the parts seen
      // at a slant weigh more than in the mesh's own colours. Blending the ramp in linear light instead misses by 17/255.
      const hot = await frame();
      const off = hot.insideMean.map((m, k) => Math.abs(m - heat.plan_colour[k]));
      check(`the heat map, from above, in flat colours: the heat-map PLY's colours (mean ${hot.insideMean.map((m) => m.toFixed(1)).join(" ")} ` +
        `against ${heat.plan_colour.map((m) => m.toFixed(1)).join(" ")})`, Math.max(...off) <= 5, off);
    }
  });
  process.exit(tally.failures > 0 ? 1 : 0);
})().catch((e) => {
  console.log(`not ok - html_page.js: ${(e && e.stack) || e}`);
  process.exit(1);
});
