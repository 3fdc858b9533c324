// Browser test scenarios of signing in and of the link to the robot, run by dashboard.test.mjs
// against its mobotd (the same command: node tests/web/dashboard.test.mjs --mobotd ...).
//
//   - login view: a wrong token typed in is refused with a clear error and nothing else loads (no
//     stream, no other request); a good one shows its role, the token is in neither the address
//     nor localStorage (this tab only), Sign out forgets it and closes the stream; "remember me"
//     keeps it in localStorage (a ?token= on the URL, used once and taken off the address bar, is
//     what the other scenarios open);
//   - the Link card's plot: samples drawn, round trip and pose age plausible on loopback;
//   - through link_proxy.mjs (an impairing TCP proxy in front of mobotd; the page uses relative
//     URLs, so REST and the stream go through it): cutting the link shows the banner within 3 s, a
//     key held meanwhile is not replayed after reconnection, restoring removes the banner and the
//     stream draws again; with 150 ms added each way teleop still drives and the plot's round
//     trips are >= 300 ms (the e-stop is acknowledged on the stream too); a WebSocket close with
//     4401 (what mobotd sends for a revoked or expired token) shows the login view with the reason
//     and nothing reconnects; a real token revoked by an admin shows that view within 1 s.

import { startLinkProxy } from './link_proxy.mjs';
import { restProbe } from './rest_probe.mjs';

/** The ping round trip's colour in the plot (web/src/link.ts SERIES). */
const PING_RGB = [0x38, 0xbd, 0xf8];

/**
 * @param {object} t the runner's context: browser, page (the main page, admin token), base(),
 *   token (admin), step, rest, until, sleep, screenshot, pageErrors
 */
export async function linkSteps(t) {
  const { step, sleep, screenshot } = t;
  const contexts = [];
  let proxy = null;
  let alice = null; // an operator token made here ("web login")

  /** A page of a new browser context (its own storage), errors collected like the main page's. */
  const newPage = async (name) => {
    const context = await t.browser.newContext({ viewport: { width: 1440, height: 900 } });
    contexts.push(context);
    const p = await context.newPage();
    p.on('pageerror', (error) => t.pageErrors.push(`${name} page: ${error}`));
    p.on('console', (message) => {
      if (message.type() === 'error' && !/WebSocket connection|Failed to load resource/.test(message.text())) {
        t.pageErrors.push(`${name} page console: ${message.text()}`);
      }
    });
    return p;
  };
  const session = (p) => p.evaluate(() => window.__mobot.session);
  const storage = (p) => p.evaluate(() => ({ session: sessionStorage.getItem('mobot.token'), local: localStorage.getItem('mobot.token') }));
  const truth = async () => (await t.rest(t.base(), t.token, 'GET', '/api/v1/sim/truth')).pose;
  const moved = (a, b) => Math.hypot(b.x - a.x, b.y - a.y);
  const signInWith = async (p, token, remember = false) => {
    await p.fill('[data-testid=login-token]', token);
    if (remember) await p.check('[data-testid=login-remember]');
    await p.click('[data-testid=login-submit]');
  };
  const ms = (x) => (x === null || x === undefined ? '–' : `${x.toFixed(0)} ms`);

  try {
    await step('login: a wrong token typed in is refused with a clear error; nothing else loads', async () => {
      const p = await newPage('login');
      const requests = [];
      const sockets = [];
      p.on('request', (r) => {
        const path = new URL(r.url()).pathname;
        if (path.startsWith('/api/')) requests.push(`${r.method()} ${path}`);
      });
      p.on('websocket', (ws) => sockets.push(ws.url()));
      await p.goto(`${t.base()}/`, { waitUntil: 'domcontentloaded' });
      await p.waitForSelector('[data-testid=login]', { state: 'visible', timeout: 5000 });
      if (requests.length || sockets.length) throw new Error(`before signing in the page asked ${JSON.stringify(requests)}, opened ${sockets.length} stream(s)`);
      await signInWith(p, `wrong-${t.token.slice(0, 8)}`);
      await p.waitForSelector('[data-testid=auth-error]', { state: 'visible', timeout: 3000 });
      const message = (await p.textContent('[data-testid=auth-error]')).trim();
      if (!/refused this token/.test(message)) throw new Error(`the error reads "${message}"`);
      await sleep(300);
      const s = await session(p);
      if (s.signedIn || !s.loginShown) throw new Error(`after a wrong token the session is ${JSON.stringify(s)}`);
      if (await p.isVisible('[data-testid=page-live]')) throw new Error('the dashboard is shown behind the login view');
      if (sockets.length) throw new Error(`${sockets.length} stream(s) opened with a wrong token`);
      const others = requests.filter((r) => r !== 'GET /api/v1/robot');
      if (others.length) throw new Error(`a wrong token led to ${JSON.stringify(others)}`);
      const kept = await storage(p);
      if (kept.session || kept.local) throw new Error(`a refused token was stored: ${JSON.stringify(kept)}`);
      await screenshot(p, 'login-refused.png');
      return `"${message}"; requests: ${requests.join(', ')}`;
    });

    await step('login: a good token shows its role, stays out of the URL and localStorage; Sign out forgets it and closes the stream; "remember me" keeps it in localStorage', async () => {
      alice = await t.rest(t.base(), t.token, 'POST', '/api/v1/tokens', { role: 'operator', label: 'web login' });
      const p = await newPage('login-good');
      await p.goto(`${t.base()}/`, { waitUntil: 'domcontentloaded' });
      await p.waitForSelector('[data-testid=login]', { state: 'visible', timeout: 5000 });
      const streams = [];
      p.on('websocket', (ws) => {
        const stream = { closed: false };
        streams.push(stream);
        ws.on('close', () => {
          stream.closed = true;
        });
      });
      await signInWith(p, alice.token);
      await p.waitForFunction(() => window.__mobot.connected && window.__mobot.session.role !== null, null, { timeout: 8000 });
      const role = (await p.textContent('[data-testid=session-role]')).trim();
      if (role !== 'operator') throw new Error(`the role shown is "${role}"`);
      const href = await p.evaluate(() => window.location.href);
      if (href.includes(alice.token)) throw new Error(`the token is in the address: ${href}`);
      const kept = await storage(p);
      if (kept.session !== alice.token || kept.local !== null) throw new Error(`not remembered, the token is kept as ${JSON.stringify(kept)}`);
      await screenshot(p, 'login-operator.png');
      const signOut = async () => {
        await p.click('[data-testid=signout]');
        await p.waitForSelector('[data-testid=login]', { state: 'visible', timeout: 3000 });
        await t.until('the stream to close after Sign out', () => streams.length > 0 && streams.every((s) => s.closed), 3000, 50);
        const after = await storage(p);
        if (after.session || after.local) throw new Error(`after Sign out the token is still kept: ${JSON.stringify(after)}`);
        const s = await session(p);
        if (s.signedIn || s.role !== null || (await p.evaluate(() => window.__mobot.connected))) throw new Error(`after Sign out the session is ${JSON.stringify(s)}`);
      };
      await signOut();
      // Again, remembered: kept on the device (localStorage), and forgotten there on Sign out.
      await signInWith(p, alice.token, true);
      await p.waitForFunction(() => window.__mobot.connected && window.__mobot.session.remembered, null, { timeout: 8000 });
      const remembered = await storage(p);
      if (remembered.local !== alice.token || remembered.session !== null) throw new Error(`remembered, the token is kept as ${JSON.stringify(remembered)}`);
      await signOut();
      return `role "${role}"; kept in sessionStorage, then (remember me) in localStorage; Sign out closed ${streams.length} streams and forgot it`;
    });

    await step('Link card: the latency plot is drawn (samples, ping colour on the canvas), round trip and pose age plausible', async () => {
      const page = t.page;
      await page.click('[data-testid=tab-live]');
      await page.locator('[data-testid=link-plot]').scrollIntoViewIfNeeded();
      await page.waitForFunction(() => Number(document.querySelector('[data-testid=link-plot]').dataset.samples) >= 12, null, { timeout: 5000 });
      const drawn0 = Number(await page.getAttribute('[data-testid=link-plot]', 'data-drawn'));
      await sleep(1100);
      const plot = await page.evaluate((rgb) => {
        const canvas = document.querySelector('[data-testid=link-plot]');
        const data = canvas.getContext('2d').getImageData(0, 0, canvas.width, canvas.height).data;
        let ping = 0;
        for (let i = 0; i < data.length; i += 4) {
          if (Math.abs(data[i] - rgb[0]) < 30 && Math.abs(data[i + 1] - rgb[1]) < 30 && Math.abs(data[i + 2] - rgb[2]) < 30 && data[i + 3] > 200) ping++;
        }
        const l = window.__mobot.link;
        return { samples: Number(canvas.dataset.samples), drawn: Number(canvas.dataset.drawn), topMs: Number(canvas.dataset.topMs), ping, link: { ...l, summary: l.summary(5) } };
      }, PING_RGB);
      if (!(plot.drawn > drawn0)) throw new Error(`the plot was not redrawn in 1.1 s (${drawn0} -> ${plot.drawn})`);
      if (plot.ping < 20) throw new Error(`only ${plot.ping} pixels of the ping round trip's colour on the canvas`);
      const { pingRttMs, poseAgeMs, scanAgeMs } = plot.link.summary;
      if (!(pingRttMs.count >= 3 && pingRttMs.min >= 0 && pingRttMs.max < 1000)) throw new Error(`ping round trip over 5 s: ${JSON.stringify(pingRttMs)}`);
      if (!(poseAgeMs.count >= 10 && poseAgeMs.max < 1000 && poseAgeMs.min > -50)) throw new Error(`pose age over 5 s: ${JSON.stringify(poseAgeMs)}`);
      const legend = (await page.textContent('[data-testid=link-legend]')).replace(/\s+/g, ' ').trim();
      await screenshot(page, 'link-card.png');
      const offset = plot.link.offsetMs === null ? 'no clock offset (the pongs carry no wall_us)' : `clock offset ${plot.link.offsetMs.toFixed(2)} ms ± ${(plot.link.offsetRttMs / 2).toFixed(2)}`;
      return `${plot.samples} samples, axis ${plot.topMs} ms, ${plot.ping} ping pixels; ping ${ms(pingRttMs.min)}..${ms(pingRttMs.max)}, pose age ${ms(poseAgeMs.min)}..${ms(poseAgeMs.max)}, scan age ${ms(scanAgeMs.min)}..${ms(scanAgeMs.max)}; ${offset}; ${Math.round(plot.link.bytesPerSecond / 1000)} kB/s, ${plot.link.dropped} dropped; legend "${legend}"`;
    });

    let viaProxy = null; // the page loaded through the proxy
    await step('link cut (proxy): the banner shows within 3 s, a key held meanwhile is not replayed; restored: the banner goes, the stream draws again', async () => {
      proxy = await startLinkProxy({ port: Number(new URL(t.base()).port) });
      viaProxy = await newPage('proxy');
      await viaProxy.goto(`${proxy.url}/?token=${t.token}`, { waitUntil: 'domcontentloaded' });
      await viaProxy.waitForFunction(() => window.__mobot.connected && window.__mobot.scansDrawn > 2, null, { timeout: 10_000 });
      if (proxy.connections.streams !== 1) throw new Error(`the stream does not go through the proxy (${JSON.stringify(proxy.connections)})`);
      const cutAt = Date.now();
      proxy.cut();
      await viaProxy.waitForSelector('[data-testid=link-banner]', { state: 'visible', timeout: 3000 });
      const shownMs = Date.now() - cutAt;
      const title = (await viaProxy.textContent('[data-testid=link-banner-title]')).trim();
      if (!/^Connection lost — the robot stops by itself within its teleop lease \(300 ms\); reconnecting…$/.test(title)) throw new Error(`the banner reads "${title}"`);
      // 'w' pressed while the link is down and held through the reconnection: never sent.
      await viaProxy.locator('[data-testid=map-canvas]').hover();
      await viaProxy.keyboard.down('w');
      try {
        await sleep(1000);
        await screenshot(viaProxy, 'link-banner.png');
        const banner = await viaProxy.evaluate(() => window.__mobot.banner);
        if (!(banner.attempt >= 1) || !/attempt \d+/.test(banner.detail)) throw new Error(`the banner says ${JSON.stringify(banner)}`);
        const before = await truth();
        const scans = await viaProxy.evaluate(() => window.__mobot.scansDrawn);
        const restoredAt = Date.now();
        proxy.restore();
        await viaProxy.waitForSelector('[data-testid=link-banner]', { state: 'hidden', timeout: 8000 });
        const goneMs = Date.now() - restoredAt;
        await viaProxy.waitForFunction((n) => window.__mobot.connected && window.__mobot.scansDrawn > n + 2, scans, { timeout: 5000 });
        await sleep(500);
        const after = await truth();
        const teleop = await viaProxy.evaluate(() => window.__mobot.teleop);
        if (moved(before, after) > 0.02) throw new Error(`the held key drove the robot ${moved(before, after).toFixed(3)} m after the reconnection`);
        if (teleop.seq !== 0) throw new Error(`teleop commands went out on the new connection: ${JSON.stringify(teleop)}`);
        return `banner ${shownMs} ms after the cut ("${banner.detail}"); gone ${goneMs} ms after the restore; the held key sent nothing (robot ${moved(before, after).toFixed(3)} m)`;
      } finally {
        await viaProxy.keyboard.up('w');
      }
    });

    await step('through the proxy with 150 ms each way: teleop drives, the plot\'s round trips are >= 300 ms, the e-stop is acknowledged on the stream', async () => {
      if (!viaProxy) throw new Error('no page through the proxy (the previous scenario failed)');
      proxy.setDelay(150);
      try {
        // A ping at the new delay, then drive for a second (backwards: the earlier drives may have
        // left the robot against the wall ahead of it).
        const delayedAt = Date.now();
        await sleep(1400);
        const before = await truth();
        const acksBefore = (await viaProxy.evaluate(() => window.__mobot.teleop)).acks;
        await viaProxy.locator('[data-testid=map-canvas]').hover();
        await viaProxy.keyboard.down('s');
        await sleep(1200);
        await viaProxy.keyboard.up('s');
        await sleep(500);
        const after = await truth();
        const turned = Math.abs(Math.atan2(Math.sin(after.theta - before.theta), Math.cos(after.theta - before.theta)));
        // Applied by the control loop: each command's echo came back (15 Hz for 1.2 s).
        const echoes = (await viaProxy.evaluate(() => window.__mobot.teleop)).acks - acksBefore;
        if (!(echoes >= 10)) throw new Error(`${echoes} teleop echoes through the slow link in 1.2 s (robot moved ${moved(before, after).toFixed(3)} m)`);
        if (!(moved(before, after) > 0.1 || turned > 0.3)) throw new Error(`teleop through the slow link (${echoes} echoes) moved the robot ${moved(before, after).toFixed(3)} m, turned ${turned.toFixed(2)} rad`);
        // The plot since the first pong that could have been delayed (a ping a second, 300 ms).
        const seconds = (Date.now() - delayedAt - 1400) / 1000;
        const link = await viaProxy.evaluate((s) => {
          const l = window.__mobot.link;
          return { ...l, summary: l.summary(s), teleop: window.__mobot.teleop };
        }, seconds);
        const { pingRttMs, teleopRttMs, poseAgeMs, scanAgeMs } = link.summary;
        const over = `over the last ${seconds.toFixed(1)} s`;
        if (!(pingRttMs.count >= 4 && pingRttMs.min >= 300)) throw new Error(`ping round trip ${over}: ${JSON.stringify(pingRttMs)}`);
        if (!(teleopRttMs.count >= 1 && teleopRttMs.min >= 300)) throw new Error(`teleop round trip ${over}: ${JSON.stringify(teleopRttMs)} (${JSON.stringify(link.teleop)})`);
        // A pose crossed the 150 ms one way; the clock offset is good to half its pong's round trip.
        const slackMs = (link.offsetRttMs ?? 0) / 2 + 10;
        if (!(poseAgeMs.min >= 150 - slackMs)) throw new Error(`pose age ${over}: ${JSON.stringify(poseAgeMs)} (offset ${link.offsetMs} ± ${(link.offsetRttMs ?? 0) / 2} ms)`);
        await viaProxy.locator('[data-testid=link-panel]').scrollIntoViewIfNeeded();
        await screenshot(viaProxy, 'link-slow.png');
        // The e-stop over the slow stream: acknowledged there, one round trip later.
        await viaProxy.click('[data-testid=estop]');
        await viaProxy.waitForFunction(() => window.__mobot.estopAck?.engaged === true, null, { timeout: 3000 });
        const ack = await viaProxy.evaluate(() => window.__mobot.estopAck);
        await viaProxy.click('[data-testid=estop-release]');
        await viaProxy.waitForFunction(() => window.__mobot.estopAck?.engaged === false, null, { timeout: 3000 });
        if (ack.via !== 'stream' || !(ack.elapsedMs >= 300)) throw new Error(`the e-stop was acknowledged ${JSON.stringify(ack)}`);
        const offset = link.offsetMs === null ? 'no clock offset (no wall_us in the pongs: clocks taken as in sync)' : `clock offset ${link.offsetMs.toFixed(1)} ms ± ${(link.offsetRttMs / 2).toFixed(1)}`;
        return `backed ${moved(before, after).toFixed(2)} m (${echoes} echoes, last seq ${link.teleop.seq}); ping ${ms(pingRttMs.min)}..${ms(pingRttMs.max)}, teleop echo ${ms(teleopRttMs.min)}..${ms(teleopRttMs.max)}, pose age ${ms(poseAgeMs.min)}..${ms(poseAgeMs.max)}, scan age ${ms(scanAgeMs.min)}..${ms(scanAgeMs.max)}; ${offset}; e-stop acknowledged on the stream in ${ms(ack.elapsedMs)}`;
      } finally {
        proxy.setDelay(0);
      }
    });

    await step('a stream closed with 4401 (token revoked or expired) shows the login view with the reason; nothing reconnects', async () => {
      if (!viaProxy) throw new Error('no page through the proxy (an earlier scenario failed)');
      const upgrades = proxy.stats.upgrades;
      if (proxy.closeStreams(4401, 'token revoked') !== 1) throw new Error(`no stream to close (${JSON.stringify(proxy.connections)})`);
      await viaProxy.waitForSelector('[data-testid=login]', { state: 'visible', timeout: 3000 });
      const message = (await viaProxy.textContent('[data-testid=auth-error]')).trim();
      if (!/Your token was revoked or has expired/.test(message)) throw new Error(`the login view says "${message}"`);
      // The first reconnect would go 0.5 s after a close.
      await sleep(1000);
      const state = await viaProxy.evaluate(() => ({ connection: window.__mobot.connection, session: window.__mobot.session, banner: window.__mobot.banner.shown }));
      if (state.connection !== 'auth_error' || state.session.signedIn || state.banner) throw new Error(`after 4401 the page has ${JSON.stringify(state)}`);
      if (proxy.stats.upgrades !== upgrades) throw new Error(`the page opened ${proxy.stats.upgrades - upgrades} stream(s) after 4401`);
      const kept = await storage(viaProxy);
      if (kept.session || kept.local) throw new Error(`the revoked token is still kept: ${JSON.stringify(kept)}`);
      await screenshot(viaProxy, 'login-revoked.png');
      return `"${message}"; no reconnection in 1 s, token forgotten`;
    });

    await step('a token an admin revokes (DELETE /api/v1/tokens/{id}) closes its page\'s stream at once: the login view says why', async () => {
      const revoked = await t.rest(t.base(), t.token, 'POST', '/api/v1/tokens', { role: 'viewer', label: 'web revoked' });
      const p = await newPage('revoked');
      await p.goto(`${t.base()}/`, { waitUntil: 'domcontentloaded' });
      await p.waitForSelector('[data-testid=login]', { state: 'visible', timeout: 5000 });
      await signInWith(p, revoked.token);
      await p.waitForFunction(() => window.__mobot.connected && window.__mobot.session.role === 'viewer', null, { timeout: 8000 });
      const started = Date.now();
      const reply = await restProbe(t.base(), t.token, 'DELETE', `/api/v1/tokens/${revoked.id}`);
      if (reply.status !== 204) throw new Error(`the revocation was answered ${reply.status} ${reply.text}`);
      await p.waitForSelector('[data-testid=login]', { state: 'visible', timeout: 1000 });
      const elapsedMs = Date.now() - started;
      const message = (await p.textContent('[data-testid=auth-error]')).trim();
      if (!/Your token was revoked or has expired/.test(message)) throw new Error(`the login view says "${message}"`);
      const state = await p.evaluate(() => ({ connection: window.__mobot.connection, session: window.__mobot.session }));
      if (state.connection !== 'auth_error' || state.session.signedIn) throw new Error(`after the revocation the page has ${JSON.stringify(state)}`);
      const kept = await storage(p);
      if (kept.session || kept.local) throw new Error(`the revoked token is still kept: ${JSON.stringify(kept)}`);
      return `login view ${elapsedMs} ms after the DELETE: "${message}"`;
    });
  } finally {
    for (const context of contexts) await context.close().catch(() => {});
    if (proxy) await proxy.close();
    // Nobody holds the lock for the scenarios that follow (alice drove nothing here, but a release is free).
    if (alice) await restProbe(t.base(), alice.token, 'POST', '/api/v1/operator', { action: 'release' }).catch(() => {});
  }
}
