// SPDX-License-Identifier: Apache-2.0
// What a viewer drew on a WebGL canvas: the share of its pixels that differ from the background
// colour by more than `tolerance` (the sum over red, green, blue), and their mean colour. The
// canvas needs preserveDrawingBuffer so that its last frame can still be read. Loaded by the test
// pages, and put into lasmesh's own pages by html_page.js.
function framePixels(canvas, background, tolerance) {
  const probe = document.createElement("canvas");
  probe.width = 1; probe.height = 1;
  const probeContext = probe.getContext("2d");
  probeContext.fillStyle = background;
  probeContext.fillRect(0, 0, 1, 1);
  const [br, bg, bb] = probeContext.getImageData(0, 0, 1, 1).data;
  const copy = document.createElement("canvas");
  copy.width = canvas.width; copy.height = canvas.height;
  const context = copy.getContext("2d");
  context.drawImage(canvas, 0, 0);
  const pixels = context.getImageData(0, 0, copy.width, copy.height).data;
  const width = copy.width, height = copy.height;
  const isCovered = new Uint8Array(width * height);
  let covered = 0;
  const sum = [0, 0, 0];
  for (let p = 0, i = 0; p < width * height; p++, i += 4) {
    const difference = Math.abs(pixels[i] - br) + Math.abs(pixels[i + 1] - bg) + Math.abs(pixels[i + 2] - bb);
    if (difference <= tolerance) continue;
    isCovered[p] = 1;
    covered++;
    for (let k = 0; k < 3; k++) sum[k] += pixels[i + k];
  }
  // Inside the mesh: covered pixels whose eight neighbours are covered too. Where the mesh meets
  // the background (its outline, and every hole) the multisampled pixels blend the two.
  let inside = 0;
  const insideSum = [0, 0, 0];
  for (let y = 1; y + 1 < height; y++)
    for (let x = 1; x + 1 < width; x++) {
      let all = 1;
      for (let dy = -1; dy <= 1 && all; dy++)
        for (let dx = -1; dx <= 1; dx++) all &= isCovered[(y + dy) * width + x + dx];
      if (!all) continue;
      inside++;
      for (let k = 0; k < 3; k++) insideSum[k] += pixels[4 * (y * width + x) + k];
    }
  return {
    covered: covered / (width * height),
    mean: sum.map((s) => s / Math.max(covered, 1)),
    insideMean: insideSum.map((s) => s / Math.max(inside, 1)),
  };
}
