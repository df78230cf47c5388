// A suite's index.html (hdlamp suite run, docs/lab.md) opened from disk in Debian's chromium
// (headless), as an engineer opens it offline:
//   node suite_page.cjs FILE.html SCREENSHOT.png USER_DATA_DIR
// records every request the page makes (a self-contained page makes none beyond itself), the
// page's errors, the verdict badge, the variants' summary rows, the embedded plots and their
// sizes; saves a screenshot of the top of the page; prints what it saw as one JSON line.
// Exits 1 on any failure to load.
'use strict';

const path = require('path');
const { launch } = require('./launch.cjs');

const [file, screenshot, userDataDir] = process.argv.slice(2);
if (!file || !screenshot || !userDataDir) {
	console.error('usage: node suite_page.cjs FILE.html SCREENSHOT.png USER_DATA_DIR');
	process.exit(2);
}

(async () => {
	const ctx = await launch(userDataDir, { width: 1280, height: 1400 });
	const page = await ctx.newPage();
	const requests = [];
	const pageErrors = [];
	page.on('request', (r) => requests.push(r.url()));
	page.on('pageerror', (e) => pageErrors.push(String(e)));
	const url = 'file://' + path.resolve(file);
	await page.goto(url, { waitUntil: 'load' });
	const seen = await page.evaluate(() => {
		const text = (el) => (el ? el.textContent.trim() : null);
		const svgs = [...document.querySelectorAll('svg')].map((s) => {
			const r = s.getBoundingClientRect();
			return { width: r.width, height: r.height,
				 polylines: s.querySelectorAll('polyline').length };
		});
		const tables = [...document.querySelectorAll('table')];
		return { title: document.title, h1: text(document.querySelector('h1')),
			 links: [...document.querySelectorAll('a[href]')].map((a) => a.getAttribute('href')),
			 svgs, tables: tables.length,
			 bodyText: document.body.innerText.length };
	});
	await page.screenshot({ path: screenshot });
	await ctx.close();
	console.log(JSON.stringify({ url, requests, pageErrors, ...seen }));
})().catch((e) => {
	console.error(e);
	process.exit(1);
});
