// report.test.js: layerfit's interactive reports in Debian's chromium,
// headless, driven by puppeteer-core (run by tests/cli/browser.sh, which
// makes the pages).  Prints "ok: ..." or "FAIL: ..." per check; the
// screenshots go to SHOTS for a person to look at.
//
//   node report.test.js CHROMIUM DIR SHOTS
//
// DIR holds fit.html (a joint fit of two curves, one of them named to
// break out of a script element), noconv.html (a fit stopped after one
// iteration), approach.html (a retract fit in a window, with its approach), map.html (fit --batch --report of a synthetic 8 x 8 map),
// r.csv (its results) and results.html (map r.csv --report).
'use strict';
const fs = require('fs');
const path = require('path');
const puppeteer = require('puppeteer-core');

const [chrome, dir, shots] = process.argv.slice(2);
let failed = 0;
function check(cond, what) {
  if (cond) console.log('ok: ' + what);
  else { failed++; console.log('FAIL: ' + what); }
}

// the results CSV (names without commas or quotes: the synthetic map's)
function results(file) {
  const lines = fs.readFileSync(file, 'utf8').trim().split('\n');
  const head = lines[0].split(',');
  return lines.slice(1).map(l => {
    const c = l.split(','), o = {};
    head.forEach((h, i) => { o[h] = c[i]; });
    return o;
  });
}

async function open(browser, file, hash) {
  const page = await browser.newPage();
  const errors = [];
  page.on('console', m => { if (m.type() === 'error' || m.type() === 'warning') errors.push(m.text()); });
  page.on('pageerror', e => errors.push(e.message));
  page.on('dialog', d => { errors.push('dialog: ' + d.message()); d.dismiss(); });
  page.on('request', r => { if (!r.url().startsWith('file:') && !r.url().startsWith('blob:') && !r.url().startsWith('data:')) errors.push('network: ' + r.url()); });
  await page.setViewport({ width: 1280, height: 1000 });
  await page.goto('file://' + path.resolve(dir, file) + (hash || ''), { waitUntil: 'load' });
  await page.waitForSelector('body[data-ready="1"]', { timeout: 15000 });
  return { page, errors };
}

// Wait up to 5 s for the page to reach a state (a hashchange handler runs
// after the hash is set, later on a loaded machine); the check that
// follows asserts it, so a page that never gets there still fails.
const settle = (page, fn, ...args) => page.waitForFunction(fn, { timeout: 5000 }, ...args).catch(() => {});

const canvasImage = (page, sel) => page.$eval(sel, c => c.toDataURL());

async function fitReport(browser) {
  const { page, errors } = await open(browser, 'fit.html');
  for (const id of ['parameter-table', 'correlation-table', 'curve-table', 'fit-table', 'identifiability', 'warnings', 'command-line', 'overview'])
    check(await page.$('#' + id) !== null, 'fit report: #' + id + ' is on the page');
  // the hostile name: shown as text, never markup or code
  const pwned = await page.evaluate(() => window.pwned === 1 || document.querySelectorAll('img').length > 0);
  check(!pwned, 'fit report: a file name holding </script><img onerror=...> runs nothing');
  const names = await page.$$eval('#curve-table span.name', s => s.map(e => e.title));
  check(names.some(n => n.includes('</script><img src=x onerror=window.pwned=1>&amp;\u2028.csv')), 'fit report: the hostile name is shown whole, as text');
  const json = await page.$eval('#lf-data', e => JSON.parse(e.textContent).result.curves[0].file);
  check(json.endsWith('a</script><img src=x onerror=window.pwned=1>&amp;\u2028.csv'), 'fit report: the name reads back whole from the page\'s JSON');
  // a click on the second curve's row selects it (#curve=2)
  await page.click('#curve-table tr[data-curve="2"]');
  await page.waitForFunction(() => location.hash === '#curve=2');
  // the panel is drawn by the hashchange event, after the hash is set
  await settle(page, () => { const e = document.querySelector('#curve-file'); return e && e.title.endsWith('curve2.csv'); });
  const file2 = await page.$eval('#curve-file', e => e.title);
  check(file2.endsWith('curve2.csv'), 'fit report: a click on row 2 shows curve2.csv (' + file2 + ')');
  const nums = await page.$$eval('#curve-numbers td', t => t.map(e => e.textContent));
  check(nums[0] === '2' && nums.some(t => /k = 3\b/.test(t) && /R = 1 mm/.test(t)), 'fit report: the curve panel gives its probe (' + nums.slice(0, 5).join(' | ') + ')');
  // zoom and toggle change the figure; toggling back restores it
  const fig = '#curve-panel canvas';
  const before = await canvasImage(page, fig);
  await page.click('#curve-panel button[data-zoom="zoom in"]');
  const zoomed = await canvasImage(page, fig);
  check(zoomed !== before, 'fit report: zoom in redraws the curve');
  await page.click('#curve-panel button[data-zoom="reset"]');
  check(await canvasImage(page, fig) === before, 'fit report: reset restores the view');
  await page.click('#curve-panel input[data-series="data"]');
  const hidden = await canvasImage(page, fig);
  await page.click('#curve-panel input[data-series="data"]');
  check(hidden !== before && await canvasImage(page, fig) === before, 'fit report: the data are hidden and shown again');
  // hover gives values
  const box = await (await page.$(fig)).boundingBox();
  let tip = '';
  for (let x = 0.15; x < 0.95 && !tip; x += 0.02) {
    for (let y = 0.05; y < 0.65 && !tip; y += 0.02) {
      await page.mouse.move(box.x + box.width * x, box.y + box.height * y);
      tip = await page.$eval('#curve-panel .tip', t => t.style.display === 'block' ? t.textContent : '');
    }
  }
  check(/ nm, /.test(tip), 'fit report: hovering a point gives its values (' + tip + ')');
  await page.goBack();
  await page.waitForFunction(() => location.hash === '');
  await settle(page, () => { const e = document.querySelector('#curve-file'); return e && !e.title.endsWith('curve2.csv'); });
  check(await page.$eval('#curve-file', e => e.title.endsWith('.csv') && !e.title.endsWith('curve2.csv')), 'fit report: the back button returns to curve 1');
  await page.screenshot({ path: path.join(shots, 'fit.png'), fullPage: true });
  check(errors.length === 0, 'fit report: no console error (' + errors.join(' | ') + ')');
  await page.close();
}

async function approachReport(browser) {
  const { page, errors } = await open(browser, 'approach.html');
  const legend = await page.$$eval('#curve-panel input[data-series]', b => b.map(e => e.getAttribute('data-series')));
  check(legend.includes('approach (not fitted)') && legend.includes('data'), 'approach: the segment not fitted is drawn greyed (' + legend.join(', ') + ')');
  check(legend.includes('fit window'), 'approach: the fit window is marked');
  check(legend.some(n => /^measured adhesion \d/.test(n)), 'approach: the measured adhesion is named');
  check(await page.$('#observed-table') !== null, 'approach: the table of what was measured without a model');
  await page.screenshot({ path: path.join(shots, 'window.png'), fullPage: true });
  check(errors.length === 0, 'approach: no console error (' + errors.join(' | ') + ')');
  await page.close();
}

async function noconvReport(browser) {
  const { page, errors } = await open(browser, 'noconv.html');
  check(await page.$eval('main', m => /The fit did not converge/.test(m.textContent)), 'not converged: said at the top');
  check(await page.$('#curve-panel .fig.noconv') !== null, 'not converged: its figure is marked');
  await page.screenshot({ path: path.join(shots, 'noconv.png') });
  check(errors.length === 0, 'not converged: no console error (' + errors.join(' | ') + ')');
  await page.close();
}

async function mapReport(browser) {
  const rows = results(path.join(dir, 'r.csv'));
  const { page, errors } = await open(browser, 'map.html');
  for (const id of ['heatmap-w_J_m2', 'heatmap-Estar_Pa', 'heatmap-chi2_dof', 'heatmap-status', 'hist-w_J_m2', 'results-table', 'export-plan'])
    check(await page.$('#' + id) !== null, 'map report: #' + id + ' is on the page');
  // the pixel in column 2, row 5 from the bottom (distinct x and y)
  const xs = [...new Set(rows.map(r => +r.x_m))].sort((a, b) => a - b);
  const ys = [...new Set(rows.map(r => +r.y_m))].sort((a, b) => a - b);
  const want = rows.findIndex(r => +r.x_m === xs[2] && +r.y_m === ys[5]) + 1;
  const cv = await page.$('#heatmap-w_J_m2');
  const b = await cv.boundingBox();
  const nx = xs.length, ny = ys.length;
  await page.mouse.move(b.x + (2.5 / nx) * b.width, b.y + ((ny - 1 - 5) + 0.5) / ny * b.height);
  const title = await page.$eval('#heatmap-w_J_m2', c => c.title);
  check(title.startsWith('fit ' + want + ' (' + rows[want - 1].status + '): ') && title.endsWith(' mJ/m²'), 'map report: the pixel under the pointer names its fit and w (' + title + ')');
  await page.mouse.click(b.x + (2.5 / nx) * b.width, b.y + ((ny - 1 - 5) + 0.5) / ny * b.height);
  await page.waitForFunction(() => /curve=\d+/.test(location.hash), { timeout: 5000 }).catch(() => {});
  const hash = await page.evaluate(() => location.hash);
  await settle(page, f => { const e = document.querySelector('#curve-file'); return e && e.title === f; }, rows[want - 1].file);
  check(hash === '#curve=' + want, 'map report: a click on pixel (2, 5) selects fit ' + want + ' (' + hash + ')');
  const row = rows[want - 1];
  const file = await page.$eval('#curve-file', e => e.title);
  check(file === row.file, 'map report: the curve panel names its file (' + file + ')');
  const w = await page.$$eval('#curve-numbers td', t => t.map(e => e.textContent));
  const wtext = (+row.w_J_m2 * 1e3).toPrecision(4).replace(/\.?0+$/, '') + ' mJ/m²';
  check(w.includes(wtext), 'map report: the curve panel gives its w, ' + wtext);
  check(await page.$('#curve-panel canvas') !== null, 'map report: the curve panel draws the curve and its fit');
  // zoom and toggle in the panel
  const fig = '#curve-panel canvas';
  const before = await canvasImage(page, fig);
  await page.click('#curve-panel button[data-zoom="zoom in"]');
  check(await canvasImage(page, fig) !== before, 'map report: zoom in redraws the curve');
  await page.click('#curve-panel input[data-series="model, stable"]');
  const hidden = await canvasImage(page, fig);
  await page.click('#curve-panel input[data-series="model, stable"]');
  check(hidden !== await canvasImage(page, fig), 'map report: the model is hidden and shown again');
  const pop = await page.$$eval('#population-summary tr', t => t.map(r => Array.from(r.cells, c => c.textContent)));
  check(pop.length === 3 && pop[1][0] === 'all' && pop[1][1] === 'w' && pop[1][2] === String(rows.length),
        'map report: the batch\'s population summary of w and E* (' + (pop[1] || []).slice(0, 4).join(' | ') + ')');
  await page.screenshot({ path: path.join(shots, 'map.png'), fullPage: true });
  // exclude this fit, then export the kept ones as a plan
  await page.click('#curve-keep');
  const csv = await page.evaluate(async () => {
    const a = document.getElementById('export-plan');
    return { name: a.getAttribute('download'), href: a.href, text: await (await fetch(a.href)).text() };
  });
  const lines = csv.text.trim().split('\n');
  check(csv.href.startsWith('blob:') && csv.name.endsWith('.csv'), 'map report: the export is a download from a Blob (' + csv.name + ')');
  check(lines[0] === 'file,index,sample,k,R_m,b_m,interface,nu,segment', 'map report: the export is a plan (' + lines[0] + ')');
  check(lines.length - 1 === rows.length - 1, 'map report: the export keeps ' + (rows.length - 1) + ' of ' + rows.length + ' curves (' + (lines.length - 1) + ')');
  check(!lines.some(l => l.startsWith(row.file + ',')) && lines.some(l => l.startsWith(rows[0].file + ',')), 'map report: the excluded curve is not in the plan, the others are');
  fs.writeFileSync(path.join(dir, 'kept.csv'), csv.text);
  // the filter: only fits with w above the median, and the table follows
  const med = rows.map(r => +r.w_J_m2).sort((a, b) => a - b)[rows.length >> 1];
  await page.$eval('#filter-min', (e, v) => { e.value = String(v); e.dispatchEvent(new Event('input')); }, med);
  const shown = await page.$$eval('#results-table tr[data-row]', t => t.length);
  const expect = rows.filter(r => +r.w_J_m2 >= med).length;
  check(shown === Math.min(100, expect), 'map report: the filter w >= median shows ' + expect + ' rows (' + shown + ')');
  // back: the selection goes, the address too
  await page.goBack();
  await page.waitForFunction(() => location.hash === '');
  await settle(page, () => document.querySelector('#curve-panel').hidden);
  check(await page.$eval('#curve-panel', e => e.hidden), 'map report: the back button closes the curve');
  check(errors.length === 0, 'map report: no console error (' + errors.join(' | ') + ')');
  await page.close();
}

// `layerfit map r.csv --report`: the results alone, the same maps; a click
// draws the curve redrawn from its file, as the batch's page draws it
async function resultsOnly(browser) {
  const { page, errors } = await open(browser, 'results.html', '#curve=3');
  check(await page.$('#heatmap-w_J_m2') !== null, 'results page: the heat map of w');
  const rows = results(path.join(dir, 'r.csv'));
  check(await page.$eval('#curve-file', e => e.title) === rows[2].file, 'results page: #curve=3 opens fit 3');
  check(await page.$('#curve-panel canvas') !== null, 'results page: the curve panel draws the curve and its fit');
  const batch = await open(browser, 'map.html', '#curve=3');
  check(await canvasImage(page, '#curve-panel canvas') === await canvasImage(batch.page, '#curve-panel canvas'),
        'results page: curve 3 drawn as the batch page draws it');
  await batch.page.close();
  const head = await page.evaluate(async () => (await (await fetch(document.getElementById('export-plan').href)).text()).split('\n')[0]);
  check(head === 'file,index,sample,k,R_m,b_m,interface,nu,segment', 'results page: the export is a plan (' + head + ')');
  await page.screenshot({ path: path.join(shots, 'results.png'), fullPage: true });
  check(errors.length === 0, 'results page: no console error (' + errors.join(' | ') + ')');
  await page.close();
}

(async () => {
  fs.mkdirSync(shots, { recursive: true });
  const profile = fs.mkdtempSync(path.join(dir, 'profile-'));
  const browser = await puppeteer.launch({
    executablePath: chrome, userDataDir: profile, headless: true,
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
           '--disable-background-networking', '--disable-component-update', '--disable-sync']
  });
  try {
    await fitReport(browser);
    await noconvReport(browser);
    await approachReport(browser);
    await mapReport(browser);
    await resultsOnly(browser);
  } finally {
    await browser.close();
  }
  process.exit(failed ? 1 : 0);
})().catch(e => { console.log('FAIL: ' + (e && e.stack || e)); process.exit(1); });
