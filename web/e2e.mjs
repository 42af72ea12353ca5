// Drives the built page in headless Chromium (Debian's /usr/bin/chromium) and prints one JSON
// object for crates/bounce-web/tests/browser.rs to check. Usage: node e2e.mjs URL SCREENSHOT.png
// MODE where MODE is "webgl" (the viewer), "fallback" (the 2D canvas page), "fallback-scenario"
// (the 2D canvas with ?scenario=mixing) or "fps".
import { open, sleep } from "./chromium.mjs";

const [url, screenshot, mode] = process.argv.slice(2);
const stepOf = (status) => Number(/step (\d+)/.exec(status)[1]);
// Waits (up to a minute: a cold headless Chromium renders the first frames slowly) until the
// status of `window[api]` says the simulation is past step `n`.
const pastStep = (page, api, n) =>
  page.waitForFunction(
    ({ api, n }) => {
      // The viewer's status throws until its first frame has built the app.
      try { return Number(/step (\d+)/.exec(window[api].status())[1]) > n; } catch { return false; }
    },
    { api, n },
    { timeout: 60000 },
  );

const { page, errors, close } = await open({ width: 1280, height: 800 });
const result = { mode, errors };
try {
  if (mode === "webgl") {
    await page.goto(`${url}/index.html?scenario=gas`);
    await page.waitForFunction(() => window.bounce !== undefined, null, { timeout: 90000 });
    // Frames advance the simulation (how fast depends on the machine, not asserted).
    await pastStep(page, "bounce", 5);
    result.running = await page.evaluate(() => window.bounce.status());
    await page.screenshot({ path: screenshot });
    result.buttons = await page.evaluate(() => window.bounce.buttons());
    const [, px, py, , sx, sy] = result.buttons.split(" ").map(Number);
    await page.mouse.click(px, py); // pause: takes effect at the next frame
    await page.waitForFunction(() => / running false/.test(window.bounce.status()), null, { timeout: 60000 });
    result.paused_a = await page.evaluate(() => window.bounce.status());
    await sleep(700);
    result.paused_b = await page.evaluate(() => window.bounce.status());
    await page.mouse.click(sx, sy); // one step
    await pastStep(page, "bounce", stepOf(result.paused_b));
    await sleep(500);
    result.stepped = await page.evaluate(() => window.bounce.status());
    await page.mouse.click(px, py); // play again
    await pastStep(page, "bounce", stepOf(result.stepped) + 2);
    result.resumed = await page.evaluate(() => window.bounce.status());
    // The method switch in the panel: exact hard discs from the scene's start, and back.
    const names = result.buttons.split(" ");
    const at = (name) => [1, 2].map((k) => Number(names[names.indexOf(name) + k]));
    await page.mouse.click(...at("event_driven"));
    await page.waitForFunction(() => / method event_driven$/.test(window.bounce.status()), null, { timeout: 60000 });
    result.exact = await page.evaluate(() => window.bounce.status());
    await page.mouse.click(...at("time_stepped"));
    await page.waitForFunction(() => / method time_stepped$/.test(window.bounce.status()), null, { timeout: 60000 });
    result.stepped_again = await page.evaluate(() => window.bounce.status());
    await page.evaluate(() => window.bounce.open_builtin("gas"));
    result.hash_100 = await page.evaluate(() => window.bounce.run_to(100));
    // Exact hard discs, the event-driven method, in the page's own build.
    await page.evaluate(() => window.bounce.open_builtin("hard-discs"));
    result.hard_20 = await page.evaluate(() => window.bounce.run_to(20));
  } else if (mode === "fps") {
    // Frame rate with 20,000 discs (for the record, not an assertion).
    await page.goto(`${url}/index.html?scenario=gas`);
    await page.waitForFunction(() => window.bounce !== undefined, null, { timeout: 90000 });
    const text = `[world]\nmin = [0.0, 0.0]\nmax = [230.0, 230.0]\n[time]\ndt = 0.016666666666666666\nsteps = 100000\n[[gas]]\ncount = 20000\nradius = 0.5\nuniform = 2.0\nseed = 1\n`;
    await page.evaluate((t) => { window.bounce.open_text("gas-20k", t); window.bounce.set_running(true); }, text);
    await sleep(6000);
    result.status = await page.evaluate(() => window.bounce.status());
    await page.screenshot({ path: screenshot });
  } else if (mode === "fallback-scenario") {
    // The 2D canvas honours ?scenario= and the scenario's colours.
    await page.goto(`${url}/index.html?scenario=mixing&no-webgl`);
    await page.waitForFunction(() => window.bounceFallback !== undefined, null, { timeout: 90000 });
    await pastStep(page, "bounceFallback", 2);
    await page.click("#play");
    result.status = await page.evaluate(() => window.bounceFallback.status());
    await page.screenshot({ path: screenshot });
  } else {
    await page.goto(`${url}/index.html?scenario=gas&no-webgl`);
    await page.waitForFunction(() => window.bounceFallback !== undefined, null, { timeout: 90000 });
    await pastStep(page, "bounceFallback", 5);
    result.running = await page.evaluate(() => window.bounceFallback.status());
    await page.screenshot({ path: screenshot });
    await page.click("#play");
    await sleep(300);
    result.paused_a = await page.evaluate(() => window.bounceFallback.status());
    await sleep(500);
    result.paused_b = await page.evaluate(() => window.bounceFallback.status());
    await page.click("#step");
    await sleep(300);
    result.stepped = await page.evaluate(() => window.bounceFallback.status());
    await page.click("#play");
    await pastStep(page, "bounceFallback", stepOf(result.stepped) + 2);
    result.resumed = await page.evaluate(() => window.bounceFallback.status());
    result.hash_100 = await page.evaluate(() => window.bounceFallback.runTo("gas", 100));
    result.hard_20 = await page.evaluate(() => window.bounceFallback.runTo("hard-discs", 20));
    result.galton_300 = await page.evaluate(() => window.bounceFallback.runTo("galton-board", 300));
    result.repose_2500 = await page.evaluate(() => window.bounceFallback.runTo("angle-of-repose", 2500));
    result.repose_turned = await page.evaluate(() => window.bounceFallback.turned("angle-of-repose", 300));
    result.effusion_regions = await page.evaluate(() => window.bounceFallback.regions("effusion"));
    result.hourglass_regions = await page.evaluate(() => window.bounceFallback.regions("hourglass"));
    result.hourglass_sensed = await page.evaluate(() => window.bounceFallback.sensed("hourglass", 600));
    result.gas_flashes = await page.evaluate(() => window.bounceFallback.flashes("gas", 20));
    result.shear_marks = await page.evaluate(() => window.bounceFallback.slides("shear", 50));
    result.gas_marks = await page.evaluate(() => window.bounceFallback.slides("gas", 1));
    await page.check("#flash");
    await sleep(300);
    result.flashing = await page.evaluate(() => document.getElementById("flash").checked);
  }
  if (mode === "webgl" || mode === "fallback") {
    result.steps = ["running", "paused_a", "paused_b", "stepped", "resumed"].map((k) => stepOf(result[k]));
  }
} catch (e) {
  result.error = String(e);
}
await close();
console.log(JSON.stringify(result));
