// The live page of tools/demo (the closed loop with the in-process reference ECU) in Debian's
// chromium (headless):
//   node demo_page.cjs URL SCREENSHOT.png USER_DATA_DIR
// loads URL, waits until the oncoming car is in the camera's view, masked, between 50 and 110 m
// (close enough to be seen in the picture) and the page shows it: the glare table's row, the
// loop panel's entry with its latencies, a lit image. Then saves a screenshot of the page down to
// the loop panel, and prints what it saw — the panels, /status read at the same instant, the
// image's statistics — as one JSON line. Exits 1 on any failure.
'use strict';

const { launch } = require('./launch.cjs');

const [url, screenshot, userDataDir] = process.argv.slice(2);
if (!url || !screenshot || !userDataDir) {
	console.error('usage: node demo_page.cjs URL SCREENSHOT.png USER_DATA_DIR');
	process.exit(2);
}

async function seen() {
	const img = document.getElementById('live');
	let image = null;
	if (img && img.complete && img.naturalWidth > 0) {
		const c = document.createElement('canvas');
		c.width = img.naturalWidth;
		c.height = img.naturalHeight;
		const g = c.getContext('2d');
		g.drawImage(img, 0, 0);
		const d = g.getImageData(0, 0, c.width, c.height).data;
		let sum = 0, sum2 = 0;
		const n = d.length / 4;
		for (let i = 0; i < d.length; i += 4) {
			const y = 0.2126 * d[i] + 0.7152 * d[i + 1] + 0.0722 * d[i + 2];
			sum += y;
			sum2 += y * y;
		}
		image = { width: c.width, height: c.height, mean: sum / n,
			  stddev: Math.sqrt(sum2 / n - (sum / n) ** 2) };
	}
	const rows = [...document.querySelectorAll('#glare tbody tr')].map(
		(r) => ({ actor: r.dataset.actor, cells: [...r.cells].map((c) => c.textContent) }));
	const head = document.querySelector('#loop [data-key="last_enter"]');
	const actors = [...document.querySelectorAll('#loop [data-actor]')].map(
		(d) => ({ id: d.dataset.actor, text: d.textContent, cls: d.className }));
	let status = null;
	try {
		const r = await fetch('/status', { cache: 'no-store' });
		status = await r.json();
	} catch (e) {
		status = null;
	}
	return { image, scene: document.getElementById('scene').textContent, glareRows: rows,
		 loopHead: head ? head.textContent : null, loopActors: actors,
		 status: status && { scene: status.scene, glare: status.glare,
				     last_enter: status.loop && status.loop.last_enter } };
}

function ready(s) {
	if (!s.image || s.image.mean < 10 || s.image.stddev < 5 || !s.status || !s.status.glare)
		return false;
	const row = s.glareRows.find((r) => r.actor === 'oncoming-car');
	const g = s.status.glare.find((x) => x.id === 'oncoming-car');
	const e = s.status.last_enter;
	const m = row ? Number(row.cells[1]) : NaN;
	return row && g && e && e.masked && e.actor === 'oncoming-car' && m >= 50 && m <= 110 &&
	       g.pass && row.cells[5] === 'pass' && /mask \d+\.\d ms/.test(s.loopHead || '') &&
	       !/not masked/.test(s.loopHead) &&
	       /* the page and /status on the same pass of the loop */
	       s.loopHead.includes('mask ' + Number(e.latency_ms.mask).toFixed(1) + ' ms');
}

(async () => {
	// tall enough for the picture and the panels below it: no resize when the picture is taken
		const browser = await launch(userDataDir, { width: 1280, height: 1100 });
	try {
		const page = browser.pages()[0] || await browser.newPage();
		const errors = [];
		page.on('pageerror', (e) => errors.push(String(e)));
		await page.goto(url, { waitUntil: 'domcontentloaded' });
		// a pass of the scenario lasts ~10 s: a missed window comes again
		const until = Date.now() + 120000;
		let s;
		for (;;) {
			s = await page.evaluate(seen);
			if (ready(s))
				break;
			if (Date.now() > until)
				throw new Error(`timed out; last seen ${JSON.stringify(s)}`);
			await page.waitForTimeout(100);
		}
		// the picture and, below it at this width, the glare and loop panels
		const bottom = await page.evaluate(
			() => document.getElementById('loop').getBoundingClientRect().bottom + window.scrollY);
		await page.screenshot({ path: screenshot,
					clip: { x: 0, y: 0, width: 1280, height: Math.ceil(bottom) + 16 } });
		s.pageErrors = errors;
		console.log(JSON.stringify(s));
	} finally {
		await browser.close();
	}
})().catch((e) => {
	console.error(`demo_page: ${e.stack || e}`);
	process.exit(1);
});
