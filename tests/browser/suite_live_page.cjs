// The live page of hdlampd --suite (docs/lab.md "In real time") in Debian's chromium (headless):
//   node suite_live_page.cjs URL SCREENSHOT.png USER_DATA_DIR
// loads URL, waits until the Suite panel shows the variant running, its photometers against the
// limit and bins with samples, then saves a screenshot and prints what the panel and /status
// said at that instant as one JSON line. Exits 1 when the panel never fills.
'use strict';

const { launch } = require('./launch.cjs');

const [url, screenshot, userDataDir] = process.argv.slice(2);
if (!url || !screenshot || !userDataDir) {
	console.error('usage: node suite_live_page.cjs URL SCREENSHOT.png USER_DATA_DIR');
	process.exit(2);
}

async function seen() {
	const rows = (sel, key) => [...document.querySelectorAll(sel)].map(
		(r) => ({ key: r.dataset[key], cells: [...r.cells].map((c) => c.textContent) }));
	let status = null;
	try {
		const r = await fetch('/status', { cache: 'no-store' });
		status = (await r.json()).suite || null;
	} catch (e) {
		status = null;
	}
	const head = document.querySelector('#suite [data-key="current"]');
	return { head: head ? head.textContent : null,
		 photometers: rows('#suite-photometers tbody tr', 'photometer'),
		 bins: rows('#suite-bins tbody tr', 'bin'), status };
}

(async () => {
	const ctx = await launch(userDataDir, { width: 1280, height: 1000 });
	const page = await ctx.newPage();
	const pageErrors = [];
	page.on('pageerror', (e) => pageErrors.push(String(e)));
	await page.goto(url);
	const t0 = Date.now();
	let s = null;
	while (Date.now() - t0 < 120000) {
		s = await page.evaluate(seen);
		if (s.photometers.length && s.bins.some((b) => Number(b.cells[1]) > 0))
			break;
		await page.waitForTimeout(200);
	}
	await page.locator('#suite').screenshot({ path: screenshot });
	await ctx.close();
	console.log(JSON.stringify({ pageErrors, ...s }));
	process.exit(s && s.photometers.length ? 0 : 1);
})().catch((e) => {
	console.error(e);
	process.exit(1);
});
