// Headless Chromium (Debian's /usr/bin/chromium, software GL) for the browser tests' drivers
// (e2e.mjs, widget-e2e.mjs, jupyter-e2e.mjs): a fresh profile, a page whose errors are
// collected, and a close that removes the profile.
import { chromium } from "playwright-core";
import { mkdtempSync, rmSync } from "node:fs";
import { tmpdir } from "node:os";
import { join } from "node:path";

// Opens a page of `width` × `height` CSS pixels (device scale 1); `consoleErrors` also
// collects the console's errors beside uncaught ones.
export async function open({ width, height, consoleErrors = false }) {
  const profile = mkdtempSync(join(tmpdir(), "bounce-chromium-"));
  const context = await chromium.launchPersistentContext(profile, {
    executablePath: "/usr/bin/chromium",
    headless: true,
    viewport: { width, height },
    deviceScaleFactor: 1,
    args: [
      "--no-sandbox", "--disable-gpu", "--enable-unsafe-swiftshader",
      "--disable-background-networking", "--disable-component-update", "--disable-sync",
      "--no-first-run", "--disable-quic",
    ],
  });
  const page = context.pages()[0] || (await context.newPage());
  const errors = [];
  page.on("pageerror", (e) => errors.push(String(e)));
  if (consoleErrors) page.on("console", (m) => { if (m.type() === "error") errors.push(m.text()); });
  const close = async () => {
    await context.close();
    rmSync(profile, { recursive: true, force: true });
  };
  return { page, errors, close };
}

export const sleep = (ms) => new Promise((r) => setTimeout(r, ms));
