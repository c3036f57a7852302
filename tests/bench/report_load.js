// report_load.js: how long a map report takes to open in Chromium (not
// part of `make check`; tests/bench/report.sh runs it).
//
//   node report_load.js CHROMIUM PAGE.html
//
// Prints, in ms: from navigation to the page drawn and clickable (the
// script's data-ready mark), a click on the middle of the heat map of w to
// that curve drawn, and the status filter set to "ok".
'use strict';
const fs = require('fs');
const path = require('path');
const puppeteer = require(path.join(__dirname, '..', 'browser', 'node_modules', 'puppeteer-core'));

(async () => {
  const [chrome, file] = process.argv.slice(2);
  const profile = fs.mkdtempSync(path.join(require('os').tmpdir(), 'layerfit-report-'));
  const browser = await puppeteer.launch({
    executablePath: chrome, userDataDir: profile, headless: true,
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
           '--disable-background-networking', '--disable-component-update', '--disable-sync']
  });
  const page = await browser.newPage();
  await page.setViewport({ width: 1280, height: 900 });
  const t0 = Date.now();
  await page.goto('file://' + path.resolve(file), { waitUntil: 'load' });
  await page.waitForSelector('body[data-ready="1"]', { timeout: 120000 });
  const t1 = Date.now();
  const b = await (await page.$('#heatmap-w_J_m2')).boundingBox();
  const t2 = Date.now();
  await page.mouse.click(b.x + b.width / 2, b.y + b.height / 2);
  await page.waitForSelector('#curve-panel canvas', { timeout: 60000 });
  const t3 = Date.now();
  await page.select('#filter-status', 'ok');
  const t4 = Date.now();
  console.log('page ' + (fs.statSync(file).size / 1e6).toFixed(1) + ' MB: clickable after ' + (t1 - t0) +
              ' ms, a pixel\'s curve in ' + (t3 - t2) + ' ms, the status filter in ' + (t4 - t3) + ' ms');
  await browser.close();
  fs.rmSync(profile, { recursive: true, force: true });
})().catch(e => { console.error(e); process.exit(1); });
