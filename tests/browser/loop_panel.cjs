// The live view's "Loop" panel (docs/loop.md) in Debian's chromium (headless):
//   node loop_panel.cjs URL USER_DATA_DIR
// loads URL, waits until the panel lists a road user glared in frames, and prints what the
// panel shows as one JSON line: its first line, each road user's line and class, page errors.
// Exits 1 on any failure.
'use strict';

const { launch } = require('./launch.cjs');

const [url, userDataDir] = process.argv.slice(2);
if (!url || !userDataDir) {
	console.error('usage: node loop_panel.cjs URL USER_DATA_DIR');
	process.exit(2);
}

function panel() {
	const head = document.querySelector('#loop [data-key="last_enter"]');
	return {
		head: head ? head.textContent : null,
		actors: [...document.querySelectorAll('#loop [data-actor]')].map(
			(d) => ({ id: d.dataset.actor, text: d.textContent, cls: d.className })),
	};
}

(async () => {
	const browser = await launch(userDataDir);
	try {
		const page = browser.pages()[0] || await browser.newPage();
		const errors = [];
		page.on('pageerror', (e) => errors.push(String(e)));
		await page.goto(url, { waitUntil: 'domcontentloaded' });
		const until = Date.now() + 30000;
		let seen;
		for (;;) {
			seen = await page.evaluate(panel);
			if (seen.actors.some((a) => / [1-9][0-9]* frames unseen/.test(a.text)))
				break;
			if (Date.now() > until)
				throw new Error(`timed out; last seen ${JSON.stringify(seen)}`);
			await page.waitForTimeout(250);
		}
		seen.pageErrors = errors;
		console.log(JSON.stringify(seen));
	} finally {
		await browser.close();
	}
})().catch((e) => {
	console.error(`loop_panel: ${e.stack || e}`);
	process.exit(1);
});
