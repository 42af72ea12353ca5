// Drives bounce's notebook view (crates/bounce-py/python/bounce/widget.js) in headless
// Chromium through the harness page crates/bounce-py/tests/widget/harness.html, and prints one
// JSON object for crates/bounce-py/tests/test_widget.py to check.
// Usage: node widget-e2e.mjs URL SCREENSHOT.png MODE [RENDERER], MODE one of "render" (draw
// one frame and screenshot it), "controls" (play, pause, step) or "fps" (frames drawn a
// second while playing, the stand-in kernel answering each request at once).
import { open, sleep } from "./chromium.mjs";

const [url, screenshot, mode, renderer = "auto"] = process.argv.slice(2);
const { page, errors, close } = await open({ width: 1100, height: 900, consoleErrors: true });
const result = { mode, errors };
const draws = () => page.evaluate(() => window.harness.el.bounce.draws);
const status = () => page.evaluate(() => window.harness.el.querySelector(".bounce-status").textContent);
try {
  const frames = mode === "render" ? 1 : mode === "controls" ? 3 : 8;
  await page.goto(`${url}/harness.html?frames=${frames}&renderer=${renderer}`);
  await page.waitForFunction(() => window.harness && window.harness.el.bounce.draws > 0, null, { timeout: 90000 });
  result.renderer = await page.evaluate(() => window.harness.el.bounce.renderer);
  if (mode === "render") {
    result.canvas = await page.evaluate(() => {
      const r = window.harness.el.bounce.canvas().getBoundingClientRect();
      return [r.left, r.top, r.width, r.height];
    });
    result.histogram = await page.evaluate(() => {
      const c = window.harness.el.querySelector(".bounce-histogram");
      const r = c.getBoundingClientRect();
      return [r.left, r.top, r.width, r.height];
    });
    result.status = await status();
    await page.screenshot({ path: screenshot });
  } else if (mode === "controls") {
    result.first = await status();
    await page.click(".bounce-play");
    await page.waitForFunction(() => window.harness.kernel.answers >= 3, null, { timeout: 30000 });
    await page.click(".bounce-play");
    await sleep(300);
    const paused = await page.evaluate(() => window.harness.kernel.answers);
    await sleep(700);
    result.paused_answers = [paused, await page.evaluate(() => window.harness.kernel.answers)];
    result.paused_status = await status();
    await page.click(".bounce-step");
    await page.waitForFunction((n) => window.harness.kernel.answers > n, result.paused_answers[1], { timeout: 30000 });
    await sleep(300);
    result.stepped_status = await status();
    result.sent = await page.evaluate(() => window.harness.model.sent.map((m) => m.type));
    result.saved = await page.evaluate(() => window.harness.model.saved);
    result.button = await page.evaluate(() => window.harness.el.querySelector(".bounce-play").textContent);
  } else {
    result.discs = await page.evaluate(() => window.harness.el.bounce.canvas() && window.harness.model.get("radii").byteLength / 4);
    await page.click(".bounce-play");
    await sleep(1500);
    const [d0, t0] = [await draws(), Date.now()];
    await sleep(5000);
    const [d1, t1] = [await draws(), Date.now()];
    result.fps = ((d1 - d0) * 1000) / (t1 - t0);
    const times = await page.evaluate(() => [...window.harness.el.bounce.drawTimes].sort((a, b) => a - b));
    result.draw_ms_median = times[Math.floor(times.length / 2)];
    result.answers = await page.evaluate(() => window.harness.kernel.answers);
    await page.click(".bounce-play");
  }
} catch (e) {
  result.error = String(e);
}
await close();
console.log(JSON.stringify(result));
