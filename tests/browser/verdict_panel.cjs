// The live page's verdict panel in Debian's chromium (headless) with playwright-core:
//   node verdict_panel.cjs URL SET_ID SCREENSHOT.png USER_DATA_DIR
// loads URL, waits until set SET_ID shows a run that failed frames ("FAIL so far") while its
// newest frame passes ("now: pass"), reads the panel at that one instant (texts, classes,
// colours, the strip's cells and the hover text of a failing cell), saves a screenshot of the
// panel, and prints what it saw as one JSON line. Exits 1 on any failure.
'use strict';

const { launch } = require('./launch.cjs');

const [url, setId, screenshot, userDataDir] = process.argv.slice(2);
if (!url || !setId || !screenshot || !userDataDir) {
	console.error('usage: node verdict_panel.cjs URL SET_ID SCREENSHOT.png USER_DATA_DIR');
	process.exit(2);
}

// The panel at one instant: every set's box, and the named set in detail.
function panel(id) {
	const text = (el) => (el ? el.textContent : null);
	const sets = [];
	let one = null;
	for (const box of document.querySelectorAll('#verdicts .set')) {
		const soFar = box.querySelector('[data-field="so-far"]');
		const m = soFar ? /failed (\d+) of/.exec(soFar.textContent) : null;
		sets.push({ id: box.dataset.set, boxClass: box.className, failed: m ? Number(m[1]) : 0 });
		if (box.dataset.set !== id)
			continue;
		const now = box.querySelector('[data-field="now"]');
		const canvas = box.querySelector('canvas.strip');
		one = {
			head: text(box.querySelector('.set-head')),
			boxClass: box.className,
			borderColor: getComputedStyle(box).borderLeftColor,
			now: text(now),
			nowClass: now ? now.lastChild.className : null,
			nowColor: now ? getComputedStyle(now.lastChild).color : null,
			soFar: text(soFar),
			soFarClass: soFar ? soFar.lastChild.className : null,
			longest: text(box.querySelector('[data-field="longest"]')),
			worst: text(box.querySelector('[data-field="worst"]')),
			cells: canvas ? canvas.dataset.cells : '',
		};
		// hover the newest failing cell: the title names the requirement
		if (canvas && one.cells.lastIndexOf('f') >= 0) {
			const i = one.cells.lastIndexOf('f');
			const r = canvas.getBoundingClientRect();
			const x = r.left + (i + 0.5) * r.width / one.cells.length;
			canvas.dispatchEvent(new MouseEvent('mousemove', { clientX: x, clientY: r.top + 1 }));
			one.hoverFail = canvas.title;
		}
	}
	return { sets, set: one, mode: text(document.getElementById('verdict-mode')) };
}

(async () => {
	const browser = await launch(userDataDir, { width: 1280, height: 1000 });
	try {
		const page = browser.pages()[0] || await browser.newPage();
		const errors = [];
		page.on('pageerror', (e) => errors.push(String(e)));
		await page.goto(url, { waitUntil: 'domcontentloaded' });
		const until = Date.now() + 180000;
		let seen;
		for (;;) {
			seen = await page.evaluate(panel, setId);
			const s = seen.set;
			if (s && s.now === 'now: pass' && s.head.endsWith('FAIL so far'))
				break;
			if (Date.now() > until)
				throw new Error(`timed out; last seen ${JSON.stringify(seen)}`);
			await page.waitForTimeout(100);
		}
		if (errors.length)
			throw new Error(`page errors: ${errors.join('; ')}`);
		const aside = await page.$('#verdicts');
		await aside.screenshot({ path: screenshot });
		console.log(JSON.stringify(seen));
	} catch (e) {
		console.error(String(e && e.stack ? e.stack : e));
		process.exitCode = 1;
	} finally {
		await browser.close();
	}
})();
