// Browser test scenarios of the operator lock and the Connected list, run by dashboard.test.mjs
// against its mobotd and page (the same command: node tests/web/dashboard.test.mjs --mobotd ...).
// A server that answers GET /api/v1/operator with 404 skips them all, saying why.
//
//   - the Operator card shows who drives; Take control makes the page's token the holder (GET
//     /operator agrees), Release frees the lock;
//   - a second token, bob (role operator, made with POST /api/v1/tokens), takes the lock through the
//     API: the page says "driven by bob", its teleop and goal controls say they are refused, and a
//     key press is refused with a message naming bob (the robot does not move);
//   - the page's admin token takes over from bob (the confirmation names him) and drives again,
//     while bob's commands are refused;
//   - three browser contexts contend: A (the admin token, from the URL), B (bob) and C (alice,
//     another operator), both signed in on the login view. B takes control; A and C see "driven by
//     bob", C's key press is refused naming him; A takes over, B sees that it lost control and its
//     key presses are refused, C sees the admin drive;
//   - A's Connected card lists both pages' streams with their labels and refreshes every 3 s (the
//     Operator card asks every 2 s); B (not an admin) has no such card.

import { Skip } from './mapping_steps.mjs';
import { restProbe } from './rest_probe.mjs';

/** The label mobotd gives the token passed with --token (the runner's, an admin). */
const ADMIN_LABEL = 'admin (--token)';

/**
 * @param {object} t the runner's context: browser, page, base(), token (admin), step, rest, until,
 *   sleep, screenshot, pageErrors (array the pages' errors go to)
 */
export async function operatorSteps(t) {
  const { page, step, sleep, screenshot } = t;
  let skip = null; // why every scenario skips
  let bob = null; // {id, token} of the operator token made here
  let contextA = null;
  let contextB = null;
  let pageA = null;
  let pageB = null;
  let alice = null; // {id, token} of a second operator token made here
  let contextC = null;
  let pageC = null;

  /** The status, error code and body of a request (no throw). */
  const call = (token, method, path, body) => restProbe(t.base(), token, method, path, body);
  const lock = async (token, action) => {
    const r = await call(token, 'POST', '/api/v1/operator', { action });
    if (r.status !== 200) throw new Error(`POST /api/v1/operator {action: ${action}} -> ${r.status} ${r.text.slice(0, 200)}`);
    return r.json;
  };
  const holder = async () => (await call(t.token, 'GET', '/api/v1/operator')).json?.holder ?? null;
  const hook = (p) => p.evaluate(() => window.__mobot.operator);
  const dismissToasts = (p) => p.$$eval('#toasts .toast', (els) => els.forEach((e) => e.click()));
  const lineOf = async (p) => (await p.textContent('[data-testid=operator-holder]'))?.trim() ?? '';
  /** Waits for the card in `state` with a line matching `pattern`; says what it showed when not. */
  const cardShows = async (p, state, pattern, timeout = 4000) => {
    await p.waitForFunction(([s, source]) => {
      const el = document.querySelector('[data-testid=operator-holder]');
      return el?.dataset.state === s && new RegExp(source).test(el.textContent ?? '');
    }, [state, pattern.source], { timeout }).catch(async () => {
      throw new Error(`the Operator card shows "${await lineOf(p)}" (${JSON.stringify(await hook(p))}), expected ${state} /${pattern.source}/`);
    });
    return lineOf(p);
  };
  const truth = async () => (await t.rest(t.base(), t.token, 'GET', '/api/v1/sim/truth')).pose;
  const moved = (a, b) => Math.hypot(b.x - a.x, b.y - a.y);
  const ready = () => {
    if (skip) throw new Skip(skip);
  };
  /** A page signed in with `token`: from the URL, or typed into the login view (`viaLogin`). */
  const openPage = async (context, token, name, viaLogin = false) => {
    const p = await context.newPage();
    p.on('pageerror', (error) => t.pageErrors.push(`${name} page: ${error}`));
    p.on('console', (message) => {
      if (message.type() === 'error' && !/WebSocket connection|Failed to load resource/.test(message.text())) {
        t.pageErrors.push(`${name} page console: ${message.text()}`);
      }
    });
    if (viaLogin) {
      await p.goto(`${t.base()}/`, { waitUntil: 'domcontentloaded' });
      await p.fill('[data-testid=login-token]', token);
      await p.click('[data-testid=login-submit]');
    } else {
      await p.goto(`${t.base()}/?token=${token}`, { waitUntil: 'domcontentloaded' });
    }
    await p.waitForFunction(() => window.__mobot && window.__mobot.connected && window.__mobot.operator.state !== 'unknown', null, { timeout: 10_000 });
    return p;
  };

  try {
    await step('operator: the card says who drives; Take control makes this page the holder (GET /operator agrees), Release frees it', async () => {
      const probe = await call(t.token, 'GET', '/api/v1/operator');
      if (probe.status === 404) {
        skip = `the server answers GET /api/v1/operator with 404 ${probe.code ?? ''}`.trim();
        throw new Skip(skip);
      }
      if (probe.status !== 200 || !probe.json || !('holder' in probe.json)) throw new Error(`GET /api/v1/operator -> ${probe.status} ${probe.text.slice(0, 200)}`);
      await page.click('[data-testid=tab-live]');
      await dismissToasts(page);
      // The earlier steps drove with this token: give its lock back (a free lock stays free).
      await lock(t.token, 'release');
      const free = await cardShows(page, 'free', /^nobody drives$/);
      await page.waitForSelector('[data-testid=operator-acquire]', { state: 'visible', timeout: 1000 });
      await page.click('[data-testid=operator-acquire]');
      const mine = await cardShows(page, 'mine', /^you drive since \d\d:\d\d from \S+$/, 3000);
      const held = await holder();
      const state = await hook(page);
      if (!held || held.token_id !== state.me) throw new Error(`GET /operator says ${JSON.stringify(held)}, the page thinks it is token ${state.me}`);
      if (!(await page.isVisible('[data-testid=operator-release]')) || (await page.isVisible('[data-testid=operator-acquire]'))) {
        throw new Error(`while this page drives the card offers ${JSON.stringify(state.buttons)}`);
      }
      await screenshot(page, 'operator-mine.png');
      await page.click('[data-testid=operator-release]');
      await cardShows(page, 'free', /^nobody drives$/, 3000);
      const after = await holder();
      if (after !== null) throw new Error(`after Release GET /operator says ${JSON.stringify(after)}`);
      return `"${free}" -> "${mine}" (${held.label}, token ${held.token_id}) -> released`;
    });

    await step('operator: bob (operator token) takes the lock through the API; the page shows "driven by bob", teleop and goals marked refused, a key press is refused naming bob', async () => {
      ready();
      bob = await t.rest(t.base(), t.token, 'POST', '/api/v1/tokens', { role: 'operator', label: 'bob' });
      const before = await truth();
      const taken = await lock(bob.token, 'acquire');
      if (taken.holder?.label !== 'bob') throw new Error(`bob's acquire answered ${JSON.stringify(taken)}`);
      await dismissToasts(page);
      // At once (before the page's next poll, most likely): the server refuses the stream teleop
      // with operator_busy and the card asks who drives right away; else the page refuses it itself.
      const pressed = Date.now();
      await page.locator('[data-testid=map-canvas]').hover();
      await page.keyboard.down('w');
      await sleep(400);
      await page.keyboard.up('w');
      await page.waitForSelector('[data-testid=toast-error]:has-text("bob")', { timeout: 3000 });
      const line = await cardShows(page, 'other', /^driven by bob since \d\d:\d\d from \S+$/, 3000);
      const shownAfter = Date.now() - pressed;
      const toastText = (await page.textContent('[data-testid=toast-error]:has-text("bob")'))?.trim();
      const how = /\(token \d+\)/.test(toastText ?? '') ? 'the server refused it (operator_busy)' : 'the page refused it (the card knew)';
      const state = await hook(page);
      const lastError = await page.evaluate(() => window.__mobot.lastError);
      if (!state.blocksCommands || !/operator_busy/.test(lastError ?? '')) {
        throw new Error(`after the refusal the page has ${JSON.stringify(state)}, lastError ${lastError}`);
      }
      await page.waitForSelector('[data-testid=operator-note]:has-text("ask them to release it")', { state: 'visible', timeout: 1000 });
      await page.waitForSelector('[data-testid=teleop-locked]:has-text("driven by bob")', { state: 'visible', timeout: 1000 });
      await page.waitForSelector('[data-testid=teleop-panel].locked', { timeout: 1000 });
      await page.waitForSelector('[data-testid=goal-set][aria-disabled=true]', { timeout: 1000 });
      await page.waitForSelector('[data-testid=goal-locked]', { state: 'visible', timeout: 1000 });
      // Set goal (key G) is refused too, with a word, and no goal mode is entered.
      await dismissToasts(page);
      await page.keyboard.press('g');
      await page.waitForSelector('[data-testid=toast-error]:has-text("Goal refused")', { timeout: 2000 });
      if ((await page.evaluate(() => window.__mobot.mapMode)) !== null) throw new Error('goal mode was entered while bob drives');
      if (state.buttons.takeOver !== (state.admin === true)) throw new Error(`Take over is ${state.buttons.takeOver ? 'offered' : 'not offered'} to a page whose admin flag is ${state.admin}`);
      const after = await truth();
      if (moved(before, after) > 0.05) throw new Error(`the robot moved ${moved(before, after).toFixed(3)} m while bob held the lock`);
      await screenshot(page, 'operator-other.png');
      return `"${line}" ${shownAfter} ms after the key press; ${how}: "${toastText}"; robot still (${moved(before, after).toFixed(3)} m)`;
    });

    await step('operator: the page (admin) takes over from bob after a confirmation naming him, and drives again; bob is refused', async () => {
      ready();
      if (!bob) throw new Error('no bob token (the previous scenario failed)');
      const admin = (await hook(page)).admin;
      if (admin !== true) throw new Error(`the page does not know its token is an admin (admin ${admin}): GET /clients -> ${(await call(t.token, 'GET', '/api/v1/clients')).status}`);
      // bob's lock lapses 10 s after his last command: he takes it again (or keeps it).
      await lock(bob.token, 'acquire');
      await cardShows(page, 'other', /^driven by bob/, 4000);
      await page.waitForSelector('[data-testid=operator-take-over]', { state: 'visible', timeout: 1000 });
      let asked = null;
      page.once('dialog', (dialog) => {
        asked = dialog.message();
        void dialog.accept();
      });
      await page.click('[data-testid=operator-take-over]');
      const line = await cardShows(page, 'mine', /^you drive/, 3000);
      if (!asked || !/bob/.test(asked)) throw new Error(`the take-over confirmation said ${JSON.stringify(asked)}`);
      const held = await holder();
      if (held?.token_id !== (await hook(page)).me || held?.label === 'bob') throw new Error(`after the take-over GET /operator says ${JSON.stringify(held)}`);
      const refused = await call(bob.token, 'POST', '/api/v1/teleop', { v: 0.1, w: 0, ttl_ms: 300 });
      if (refused.status !== 409 || refused.code !== 'operator_busy') throw new Error(`bob's teleop after the take-over -> ${refused.status} ${refused.text.slice(0, 200)}`);
      if (await page.isVisible('[data-testid=teleop-locked]')) throw new Error('the teleop card still says it is refused');
      // The page drives again: the control loop applies its commands (their echoes come back), and
      // the robot moves or turns. The earlier steps may have left it against a wall, where the
      // safety layer rightly holds it (once: 6 mm and 0.07 rad with 12 echoes): it starts again
      // from the world's start pose, in the open.
      const reset = await t.rest(t.base(), t.token, 'POST', '/api/v1/sim/reset', {});
      if (reset.ok !== true) throw new Error(`sim reset -> ${JSON.stringify(reset)}`);
      const before = await truth();
      const acksBefore = (await page.evaluate(() => window.__mobot.teleop)).acks;
      await page.locator('[data-testid=map-canvas]').hover();
      await page.keyboard.down('a');
      await page.keyboard.down('w');
      await sleep(800);
      await page.keyboard.up('w');
      await page.keyboard.up('a');
      const after = await truth();
      const acks = (await page.evaluate(() => window.__mobot.teleop)).acks - acksBefore;
      const turned = Math.abs(Math.atan2(Math.sin(after.theta - before.theta), Math.cos(after.theta - before.theta)));
      if (!(acks >= 5)) throw new Error(`${acks} teleop echoes in 0.8 s after the take-over (robot moved ${moved(before, after).toFixed(3)} m, turned ${turned.toFixed(2)} rad)`);
      if (!(moved(before, after) > 0.1 || turned > 0.2)) throw new Error(`the robot moved ${moved(before, after).toFixed(3)} m and turned ${turned.toFixed(2)} rad after the take-over (${acks} echoes)`);
      await page.click('[data-testid=operator-release]');
      await cardShows(page, 'free', /^nobody drives$/, 3000);
      return `confirmation "${asked}"; "${line}"; bob's teleop -> 409 operator_busy; drove ${moved(before, after).toFixed(2)} m, turned ${turned.toFixed(2)} rad (${acks} echoes); released`;
    });

    await step('operator: three browser contexts contend: B (bob, login view) takes control, A (admin) and C (alice, login view) see "driven by bob", C is refused; A takes over, B sees it lost control, C sees the admin', async () => {
      ready();
      if (!bob) throw new Error('no bob token (an earlier scenario failed)');
      alice = await t.rest(t.base(), t.token, 'POST', '/api/v1/tokens', { role: 'operator', label: 'alice' });
      contextA = await t.browser.newContext({ viewport: { width: 1440, height: 900 } });
      contextB = await t.browser.newContext({ viewport: { width: 1440, height: 900 } });
      contextC = await t.browser.newContext({ viewport: { width: 1440, height: 900 } });
      [pageA, pageB, pageC] = await Promise.all([
        openPage(contextA, t.token, 'A'),
        openPage(contextB, bob.token, 'B', true),
        openPage(contextC, alice.token, 'C', true),
      ]);
      // Whoever held it before lets go (bob's own release; the admin's for its own).
      await lock(bob.token, 'release');
      await lock(t.token, 'release');
      await cardShows(pageB, 'free', /^nobody drives$/, 4000);
      await pageB.click('[data-testid=operator-acquire]');
      const lineB = await cardShows(pageB, 'mine', /^you drive/, 3000);
      // Each page knows its own token from sign-in (GET /api/v1/whoami), before it has driven: A
      // (the process's admin token, id 0) and C (alice) know that the driver is somebody else.
      await pageA.waitForFunction(() => window.__mobot.operator.state === 'other' && /^driven by bob/.test(window.__mobot.operator.line), null, { timeout: 4000 }).catch(async () => {
        throw new Error(`A shows "${await lineOf(pageA)}" (${JSON.stringify(await hook(pageA))})`);
      });
      const [meA, meC] = [(await hook(pageA)).me, (await hook(pageC)).me];
      if (meA !== 0 || meC !== alice.id) throw new Error(`the pages know themselves as token ${meA} (A, admin --token: 0) and ${meC} (C, alice: ${alice.id})`);
      const lineA = await lineOf(pageA);
      await screenshot(pageA, 'operator-a-sees-bob.png');
      // C, another operator, sees bob too; its key press is refused naming him (by the server, or
      // by the page once it knows), and bob keeps the lock.
      await pageC.waitForFunction(() => /^driven by bob/.test(window.__mobot.operator.line), null, { timeout: 4000 });
      await pageC.locator('[data-testid=map-canvas]').hover();
      await pageC.keyboard.down('w');
      await sleep(300);
      await pageC.keyboard.up('w');
      await pageC.waitForSelector('[data-testid=toast-error]:has-text("bob")', { timeout: 3000 });
      const refusedC = (await pageC.textContent('[data-testid=toast-error]:has-text("bob")')).trim();
      if ((await holder())?.label !== 'bob') throw new Error(`after C's key press GET /operator says ${JSON.stringify(await holder())}`);
      const roleC = (await pageC.textContent('[data-testid=session-role]')).trim();
      if (roleC !== 'operator') throw new Error(`C (alice) shows the role "${roleC}"`);
      await pageA.waitForSelector('[data-testid=operator-take-over]', { state: 'visible', timeout: 2000 });
      const stateB = await hook(pageB);
      if (stateB.admin !== false) throw new Error(`B (an operator token) has admin ${stateB.admin}`);
      let asked = null;
      pageA.once('dialog', (dialog) => {
        asked = dialog.message();
        void dialog.accept();
      });
      await pageA.click('[data-testid=operator-take-over]');
      await cardShows(pageA, 'mine', /^you drive/, 3000);
      if (!/bob/.test(asked ?? '')) throw new Error(`A's confirmation said ${JSON.stringify(asked)}`);
      // B: within a poll (2 s) it is somebody else's, with a word that it was taken.
      const lost = await cardShows(pageB, 'other', new RegExp(`^driven by ${ADMIN_LABEL.replace(/[()]/g, '\\$&')}`), 4000);
      await pageB.waitForSelector('[data-testid=toast-error]:has-text("took over")', { timeout: 2000 });
      await pageB.waitForSelector('[data-testid=operator-note]:has-text("took over from you")', { state: 'visible', timeout: 1000 });
      const afterB = await hook(pageB);
      if (afterB.lostTo !== ADMIN_LABEL) throw new Error(`B's lostTo is ${JSON.stringify(afterB.lostTo)}`);
      if (afterB.buttons.acquire || afterB.buttons.release || afterB.buttons.takeOver) throw new Error(`B, not an admin, is offered ${JSON.stringify(afterB.buttons)}`);
      // B's keys are refused now, saying who drives.
      const before = await truth();
      await dismissToasts(pageB);
      await pageB.locator('[data-testid=map-canvas]').hover();
      await pageB.keyboard.down('w');
      await sleep(400);
      await pageB.keyboard.up('w');
      await pageB.waitForSelector(`[data-testid=toast-error]:has-text("Teleop refused")`, { timeout: 2000 });
      const after = await truth();
      if (moved(before, after) > 0.05) throw new Error(`B's key press moved the robot ${moved(before, after).toFixed(3)} m`);
      await screenshot(pageB, 'operator-b-lost.png');
      // C never drove: it cannot tell the admin from itself (held), or knows it is not (other).
      await pageC.waitForFunction((label) => /^(held|other)$/.test(window.__mobot.operator.state) && window.__mobot.operator.line.startsWith(`driven by ${label}`), ADMIN_LABEL, { timeout: 4000 }).catch(async () => {
        throw new Error(`C shows "${await lineOf(pageC)}" (${JSON.stringify(await hook(pageC))})`);
      });
      const lineC = await lineOf(pageC);
      // C has done its part: closed, so it does not load the machine in the scenarios that follow.
      await contextC.close();
      contextC = null;
      return `B: "${lineB}"; A: "${lineA}"; C (${roleC}): refused "${refusedC}"; A confirmed "${asked}"; B: "${lost}", lostTo ${afterB.lostTo}; C: "${lineC}"`;
    });

    await step('operator: A\'s Connected card (admin) lists both pages\' streams with their labels and refreshes every 3 s; B has none', async () => {
      ready();
      if (!pageA || !pageB) throw new Error('the two pages did not open (see the previous scenario)');
      // B is no admin: GET /clients answers 403 and the card stays hidden.
      await pageB.waitForFunction(() => window.__mobot.operator.admin === false, null, { timeout: 3000 });
      if (await pageB.isVisible('[data-testid=clients-panel]')) throw new Error('B (an operator) shows the Connected card');
      await pageA.waitForSelector('[data-testid=clients-panel]', { state: 'visible', timeout: 3000 });
      await pageA.locator('[data-testid=clients-panel]').scrollIntoViewIfNeeded();
      await pageA.click('[data-testid=clients-panel] summary');
      await pageA.waitForSelector('[data-testid=client-item][data-kind=stream][data-label=bob]', { timeout: 4000 });
      const streams = await pageA.$$eval('[data-testid=client-item][data-kind=stream]', (els) => els.map((e) => ({
        label: e.dataset.label,
        text: e.innerText.replace(/\s+/g, ' ').trim(),
      })));
      const admins = streams.filter((s) => s.label === ADMIN_LABEL);
      // The main page and A: two streams of the admin token; B: bob's.
      if (admins.length < 2) throw new Error(`${admins.length} stream(s) labelled "${ADMIN_LABEL}": ${JSON.stringify(streams)}`);
      const rows = (await pageA.evaluate(() => window.__mobot.clients)).rows;
      const bobRow = rows.find((r) => r.kind === 'stream' && r.label === 'bob');
      if (bobRow.role !== 'operator' || !(bobRow.topics.length > 0) || !(bobRow.bytesSent > 0) || !/:\d+$/.test(bobRow.address)) {
        throw new Error(`bob's row: ${JSON.stringify(bobRow)}`);
      }
      const bobText = streams.find((s) => s.label === 'bob').text;
      for (const part of ['stream', 'bob', 'operator', bobRow.address, 'dropped']) {
        if (!bobText.includes(part)) throw new Error(`bob's row reads "${bobText}", without "${part}"`);
      }
      // Cadence: the list every 3 s while open, the Operator card every 2 s (nobody is refused meanwhile).
      const c0 = await pageA.evaluate(() => ({ clients: window.__mobot.clients.polls, operator: window.__mobot.operator.polls }));
      await sleep(6200);
      const c1 = await pageA.evaluate(() => ({ clients: window.__mobot.clients.polls, operator: window.__mobot.operator.polls, rows: window.__mobot.clients.rows }));
      const clientPolls = c1.clients - c0.clients;
      const operatorPolls = c1.operator - c0.operator;
      if (clientPolls < 2 || clientPolls > 3) throw new Error(`${clientPolls} GET /clients in 6.2 s (every 3 s expected)`);
      if (operatorPolls < 3 || operatorPolls > 4) throw new Error(`${operatorPolls} GET /operator in 6.2 s (every 2 s expected)`);
      const bobLater = c1.rows.find((r) => r.id === bobRow.id);
      if (!bobLater || !(bobLater.bytesSent > bobRow.bytesSent)) throw new Error(`bob's data sent did not grow: ${bobRow.bytesSent} -> ${bobLater?.bytesSent}`);
      await screenshot(pageA, 'operator-connected.png');
      return `${streams.length} streams (${admins.length} "${ADMIN_LABEL}", bob: "${bobText}"); in 6.2 s ${clientPolls} list and ${operatorPolls} lock refreshes; bob's data ${bobRow.bytesSent} -> ${bobLater.bytesSent} B`;
    });
  } finally {
    // Nobody holds the lock for the scenarios that follow.
    if (!skip) {
      await call(t.token, 'POST', '/api/v1/operator', { action: 'release' }).catch(() => {});
      if (bob) await call(bob.token, 'POST', '/api/v1/operator', { action: 'release' }).catch(() => {});
    }
    if (alice) await call(alice.token, 'POST', '/api/v1/operator', { action: 'release' }).catch(() => {});
    if (contextA) await contextA.close().catch(() => {});
    if (contextB) await contextB.close().catch(() => {});
    if (contextC) await contextC.close().catch(() => {});
  }
}
