// Opens a notebook in a running JupyterLab (started by crates/bounce-py/tests/widget/harness.py
// with the app exposed), runs every cell, presses the bounce view's play button, counts the
// steps the kernel sends for SECONDS, pauses, and prints one JSON object.
// Usage: node jupyter-e2e.mjs URL NOTEBOOK SCREENSHOT.png SECONDS
import { open, sleep } from "./chromium.mjs";

const [url, notebook, screenshot, seconds = "5"] = process.argv.slice(2);
const { page, errors, close } = await open({ width: 1400, height: 1000 });
const result = { errors };
const stepOf = (text) => Number(/step (\d+)/.exec(text)[1]);
// The notebook's kernel is up and not running a cell.
const idle = () => {
  const widget = window.jupyterapp && window.jupyterapp.shell.currentWidget;
  const kernel = widget && widget.sessionContext && widget.sessionContext.session && widget.sessionContext.session.kernel;
  return Boolean(kernel) && kernel.status === "idle";
};
const status = () => page.evaluate(() => document.querySelector(".bounce-status").textContent);
try {
  // ?reset: a fresh workspace, so only this notebook is open.
  await page.goto(`${url}/lab/tree/${notebook}?reset`);
  await page.waitForFunction(
    () => window.jupyterapp && document.querySelector(".jp-Notebook") && window.jupyterapp.serviceManager.isReady,
    null,
    { timeout: 60000 },
  );
  // Wait for the kernel before running, so no cell is queued against a starting one.
  await page.waitForFunction(idle, null, { timeout: 60000 });
  await page.evaluate(() => window.jupyterapp.commands.execute("notebook:run-all-cells"));
  await page.waitForSelector(".bounce-view .bounce-status", { timeout: 60000 });
  await page.waitForFunction(() => /discs/.test(document.querySelector(".bounce-status").textContent), null, { timeout: 60000 });
  await page.waitForFunction(idle, null, { timeout: 60000 });
  result.first = await status();
  result.renderer = await page.evaluate(() => document.querySelector(".bounce-view").parentElement.bounce.renderer);
  await page.click(".bounce-play");
  await sleep(1500);
  const [s0, d0, t0] = [stepOf(await status()), await page.evaluate(() => document.querySelector(".bounce-view").parentElement.bounce.draws), Date.now()];
  await sleep(Number(seconds) * 1000);
  const [s1, d1, t1] = [stepOf(await status()), await page.evaluate(() => document.querySelector(".bounce-view").parentElement.bounce.draws), Date.now()];
  result.frames_per_second = ((s1 - s0) * 1000) / (t1 - t0);
  result.draws_per_second = ((d1 - d0) * 1000) / (t1 - t0);
  await page.screenshot({ path: screenshot });
  await page.click(".bounce-play");
  await sleep(1000);
  const paused = stepOf(await status());
  await sleep(1000);
  result.paused = [paused, stepOf(await status())];
  await page.click(".bounce-step");
  await page.waitForFunction((n) => Number(/step (\d+)/.exec(document.querySelector(".bounce-status").textContent)[1]) > n, paused, { timeout: 30000 });
  result.stepped = await status();
} catch (e) {
  result.error = String(e);
  await page.screenshot({ path: screenshot }).catch(() => {});
}
await close();
console.log(JSON.stringify(result));
