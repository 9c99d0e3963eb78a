// SPDX-License-Identifier: Apache-2.0
// The controls of a page served by `lasmesh view`: the mesh's options as the command line spells
// them, "Mesh" to mesh again (the server re-uses its accumulated grid unless the grid changes,
// and says which it did), a progress bar while it works, "Save" to write the outputs the command
// line named, and the command line that writes the same. Every request carries the page's token.

const byId = (id) => document.getElementById(id);

// The bytes at `url`, read as they arrive; `progress(bytes, total)` after each piece (total 0
// when the server does not say).
export async function fetchBytes(url, progress) {
  const response = await fetch(url);
  if (!response.ok) throw new Error(`${url.split("?")[0]}: ${response.status} ${response.statusText}`);
  const total = Number(response.headers.get("Content-Length")) || 0;
  const reader = response.body.getReader(), pieces = [];
  let received = 0;
  for (;;) {
    const { done, value } = await reader.read();
    if (done) break;
    pieces.push(value);
    received += value.length;
    progress(received, total);
  }
  const bytes = new Uint8Array(received);
  let at = 0;
  for (const piece of pieces) bytes.set(piece, at), (at += piece.length);
  return bytes;
}

const megabytes = (n) => `${(n / 1e6).toFixed(1)} MB`;

// The mesh `lasmesh view` serves now, its loading shown in `element`.
export const fetchMesh = (token, element) => fetchBytes(`/mesh?token=${encodeURIComponent(token)}`, (got, total) => {
  element.textContent = `loading the mesh: ${megabytes(got)}${total ? ` of ${megabytes(total)}` : ""}`;
});
const fields = { grid: "opt-grid", voxel: "opt-voxel", iso: "opt-iso", surface: "opt-surface",
  simplify: "opt-simplify", min_piece: "opt-min-piece" };

// `live`: {token, state} as the server wrote it into the page; `showBytes(bytes)` shows the mesh
// data it sends; `api` is the page's window.lasmesh, given `live` for scripts and tests.
export function startLiveControls(live, showBytes, api) {
  api.live = { state: live.state, job: Promise.resolve(), reread: null, saved: null };
  const withToken = (path) => `${path}?token=${encodeURIComponent(live.token)}`;
  const status = (text, failed = false) => {
    byId("live-status").textContent = text;
    byId("live-status").className = failed ? "failed" : "";
  };
  const post = async (path, body) => {
    const response = await fetch(withToken(path), { method: "POST", headers: { "Content-Type": "application/json" },
      body: JSON.stringify(body) });
    const answer = await response.json();
    if (!response.ok) throw new Error(answer.error || response.statusText);
    return answer;
  };
  const outputs = byId("live-outputs");
  const setState = (state) => {
    for (const [key, id] of Object.entries(fields)) byId(id).value = state.options[key];
    byId("opt-grid").disabled = byId("opt-voxel").disabled = !state.grid_rereadable;
    byId("live-command").textContent = state.command;
    if (outputs.childElementCount === 0) {
      for (const path of state.outputs) {
        const label = document.createElement("label"), box = document.createElement("input");
        box.type = "checkbox";
        box.checked = true;
        box.value = path;
        label.append(box, ` ${path}`);
        outputs.append(label);
      }
      byId("save").disabled = state.outputs.length === 0;
      byId("save").title = state.outputs.length ? "" : "start lasmesh view with -o FILE to save";
    }
    api.live.state = state;
  };
  setState(live.state);
  byId("live").hidden = false;

  // While a job runs: points read of the promised total, or the step being done.
  const watchProgress = () => {
    const bar = byId("live-progress");
    bar.hidden = false;
    bar.removeAttribute("value");
    const timer = setInterval(async () => {
      try {
        const p = await (await fetch(withToken("/progress"))).json();
        if (p.stage.startsWith("reading") && p.points_total > 0) bar.value = p.points / p.points_total;
        else bar.removeAttribute("value");
        if (p.busy) status(p.stage);
      } catch (e) { /* the next poll tells */ }
    }, 200);
    return () => { clearInterval(timer); bar.hidden = true; };
  };
  const buttons = [byId("remesh"), byId("save")];
  // One job at a time, its buttons disabled while it runs; `api.live.job` settles when it ends.
  const job = (work) => {
    const disabled = buttons.map((b) => b.disabled);
    for (const b of buttons) b.disabled = true;
    const stop = watchProgress();
    api.live.job = work().catch((e) => status(e.message, true)).finally(() => {
      stop();
      buttons.forEach((b, i) => { b.disabled = disabled[i]; });
    });
    return api.live.job;
  };
  byId("remesh").addEventListener("click", () => job(async () => {
    const settings = {};
    for (const [key, id] of Object.entries(fields)) settings[key] = byId(id).value.trim();
    const state = await post("/mesh", settings);
    await showBytes(await fetchMesh(live.token, byId("live-status")));
    setState(state);
    api.live.reread = state.reread;
    status(`${state.triangles.toLocaleString("en")} triangles in ${state.seconds.toFixed(2)} s, ` +
      (state.reread ? "the points read again for the new grid" : "from the accumulated grid (no re-read)"));
  }));
  byId("save").addEventListener("click", () => job(async () => {
    const chosen = [...outputs.querySelectorAll("input:checked")].map((box) => box.value);
    const answer = await post("/save", { outputs: chosen });
    byId("live-command").textContent = answer.command;
    api.live.saved = answer;
    status(`saved ${answer.written.map((w) => w.path).join(", ")}`);
  }));
  byId("copy").addEventListener("click", () => navigator.clipboard.writeText(byId("live-command").textContent));
}
