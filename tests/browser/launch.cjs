// Debian's chromium, headless, as every browser test here starts it (playwright-core):
// a fresh user-data directory, no sandbox (root), no GPU, and none of chromium's own
// background connections (this machine's network is closed).
'use strict';

const { chromium } = require('playwright-core');

function launch(userDataDir, viewport) {
	return chromium.launchPersistentContext(userDataDir, {
		executablePath: '/usr/bin/chromium',
		headless: true,
		...(viewport ? { viewport } : {}),
		args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
		       '--disable-background-networking', '--disable-component-update', '--disable-sync'],
	});
}

module.exports = { launch };
