// Drives the HTTP live view in Debian's chromium (headless) with playwright-core:
//   node live_view.cjs URL SCREENSHOT.png USER_DATA_DIR
// loads URL, waits until the live image shows a non-black, non-uniform frame (its pixels read
// through a canvas in the page), waits until a numeric counter of the page changes, saves a
// screenshot, and prints what it saw as one JSON line. Exits 1 on any failure.
'use strict';

const { launch } = require('./launch.cjs');

const [url, screenshot, userDataDir] = process.argv.slice(2);
if (!url || !screenshot || !userDataDir) {
	console.error('usage: node live_view.cjs URL SCREENSHOT.png USER_DATA_DIR');
	process.exit(2);
}

// Statistics of the image as the page shows it now: drawn into a canvas, read back.
function imageStats() {
	const img = document.getElementById('live');
	if (!img || !img.complete || img.naturalWidth === 0)
		return null;
	const c = document.createElement('canvas');
	c.width = img.naturalWidth;
	c.height = img.naturalHeight;
	const ctx = c.getContext('2d');
	ctx.drawImage(img, 0, 0);
	const d = ctx.getImageData(0, 0, c.width, c.height).data;
	let sum = 0, sum2 = 0, lit = 0;
	const n = d.length / 4;
	for (let i = 0; i < d.length; i += 4) {
		const y = 0.2126 * d[i] + 0.7152 * d[i + 1] + 0.0722 * d[i + 2];
		sum += y;
		sum2 += y * y;
		if (y > 40)
			lit++;
	}
	const mean = sum / n;
	return { width: c.width, height: c.height, mean, stddev: Math.sqrt(sum2 / n - mean * mean),
		 litFraction: lit / n, mode: document.getElementById('mode').textContent };
}

// Every numeric counter cell of the page, by key.
function counters() {
	const out = {};
	for (const td of document.querySelectorAll('td[data-key]')) {
		const v = Number(td.textContent);
		if (td.textContent !== '' && Number.isFinite(v))
			out[td.dataset.key] = v;
	}
	out['page.updates'] = Number(document.getElementById('updates').textContent);
	return out;
}

async function poll(page, fn, ok, timeoutMs) {
	const until = Date.now() + timeoutMs;
	let last;
	while (Date.now() < until) {
		last = await page.evaluate(fn);
		if (ok(last))
			return last;
		await page.waitForTimeout(250);
	}
	throw new Error(`timed out; last seen ${JSON.stringify(last)}`);
}

(async () => {
	// A persistent context is how playwright takes a --user-data-dir: a fresh one per run.
	const browser = await launch(userDataDir, { width: 1280, height: 800 });
	const result = { url };
	try {
		const page = browser.pages()[0] || await browser.newPage();
		const errors = [];
		page.on('pageerror', (e) => errors.push(String(e)));
		const resp = await page.goto(url, { waitUntil: 'domcontentloaded' });
		result.status = resp.status();
		result.title = await page.title();

		result.image = await poll(page, imageStats,
			(s) => s && s.mean > 10 && s.stddev > 5 && s.litFraction > 0.02, 20000);

		// A counter that changes: read them all, then wait for one to differ.
		const before = await poll(page, counters, (c) => c['page.updates'] >= 1, 10000);
		const after = await poll(page, counters, (c) => Object.keys(c).some(
			(k) => k !== 'page.updates' && k in before && c[k] !== before[k]), 10000);
		result.changed = Object.keys(after).filter(
			(k) => k !== 'page.updates' && k in before && after[k] !== before[k])
			.map((k) => ({ key: k, before: before[k], after: after[k] }));
		result.counters = Object.keys(after).length;
		result.lampRows = await page.evaluate(
			() => document.querySelectorAll('#lamps tbody tr').length);

		// The capture button: the page shows the path written, or why not (403 when off).
		await page.click('#capture');
		await page.waitForFunction(
			() => document.getElementById('capture-result').textContent !== '', null,
			{ timeout: 10000 });
		result.capture = await page.textContent('#capture-result');

		// Let the stream show a fresh frame again before the picture is taken.
		result.imageAtScreenshot = await poll(page, imageStats, (s) => s && s.mean > 10, 5000);
		await page.screenshot({ path: screenshot });
		result.screenshot = screenshot;
		result.pageErrors = errors;
		console.log(JSON.stringify(result));
	} finally {
		await browser.close();
	}
})().catch((e) => {
	console.error(`live_view: ${e.stack || e}`);
	process.exit(1);
});
