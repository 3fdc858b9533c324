// The Operator card of the Live page: who drives (GET /api/v1/operator every 2 s while connected,
// and at once after a command was refused with operator_busy), Take control / Release / Take over
// (POST /api/v1/operator, whose reply is the new state), and the lock state the teleop and goal
// controls follow. The server has no "who am I": this page's token id is learnt from an acquire or
// take-over reply, or from the holder seen right after the server accepted a driving command from
// this page. The logic is operator.ts; this renders it and talks to the server.

import { ApiError } from './apierror';
import type { ApiClient } from './api';
import { holderName, operatorErrorText, operatorView, parseOperatorBody, refusalText, takeOverPrompt } from './operator';
import type { OperatorAction, OperatorHolder, OperatorView } from './operator';
import { Poller } from './poller';
import { byId, toast } from './ui';

/** GET /api/v1/operator while connected (the brief's rate: not faster). */
export const OPERATOR_POLL_MS = 2000;
/** A refusal or a new command asks at once, but not more often than this. */
const OPERATOR_MIN_GAP_MS = 500;

export interface OperatorPanelHooks {
  /** The lock state changed: the teleop and goal controls follow it. */
  changed(view: OperatorView): void;
}

export class OperatorPanel {
  /** GET /operator answered (true), 404 (false), not asked yet (null). */
  supported: boolean | null = null;
  /** The holder; undefined until asked (and while disconnected). */
  holder: OperatorHolder | null | undefined = undefined;
  /**
   * This page's token id: as the server said at sign-in (identify), or learnt from a command it
   * accepted when that answer did not come.
   */
  me: number | null = null;
  /** GET /api/v1/clients answered 200 (true) or 403 (false). */
  admin: boolean | null = null;
  lastError: string | null = null;
  /** Who took the lock from this page last (a take-over), for the card and the test hooks. */
  lostTo: string | null = null;
  view: OperatorView;
  private readonly notMe = new Set<number>();
  private readonly poller: Poller;
  private busy = false;
  /** performance.now() of a command the server accepted while the page's token id was unknown. */
  private claimedAt = 0;
  /** performance.now() of a command refused with operator_busy. */
  private refusedAt = 0;

  constructor(
    private readonly api: ApiClient,
    private readonly hooks: OperatorPanelHooks,
  ) {
    this.poller = new Poller(() => this.refresh(), { periodMs: OPERATOR_POLL_MS, minGapMs: OPERATOR_MIN_GAP_MS });
    byId('operator-acquire').addEventListener('click', () => void this.act('acquire'));
    byId('operator-release').addEventListener('click', () => void this.act('release'));
    byId('operator-take-over').addEventListener('click', () => void this.takeOver());
    this.view = this.computeView();
    this.render();
  }

  /** GET /operator requests started. */
  get polls(): number {
    return this.poller.runs;
  }

  // ---- connection, identity ----

  connected(): void {
    this.poller.start();
  }

  disconnected(): void {
    this.poller.stop();
    this.setHolder(undefined);
  }

  /** This page's token id, as the server said at sign-in (GET /api/v1/whoami). */
  identify(tokenId: number): void {
    this.me = tokenId;
    this.notMe.delete(tokenId);
    this.update();
  }

  /** Another token (signed in again): nothing learnt about the old one holds. */
  tokenChanged(): void {
    this.me = null;
    this.notMe.clear();
    this.admin = null;
    this.lostTo = null;
    this.setHolder(undefined);
  }

  setAdmin(admin: boolean | null): void {
    if (admin === this.admin) return;
    this.admin = admin;
    this.update();
  }

  /** The server accepted a driving command from this page (teleop ack, goal, follow). */
  commandAccepted(): void {
    if (this.me !== null) return;
    // The holder now is this token: the next answer says its id.
    this.claimedAt = performance.now();
    this.poller.poke();
  }

  /** A command from this page was refused with operator_busy: somebody else drives. */
  commandRefused(): void {
    this.refusedAt = performance.now();
    this.poller.poke();
  }

  /**
   * A command this page refuses itself while somebody else surely drives: says so (`what`:
   * "Teleop", "Goal") and asks the server again (the holder may have gone). Returns the error as
   * the page's hooks report it ("operator_busy: ..."), null when nothing was refused.
   */
  refuseLocally(what: string): string | null {
    if (!this.view.blocksCommands || !this.holder) return null;
    const text = `${what} refused: ${refusalText(this.holder, this.admin)}`;
    this.lastError = `operator_busy: ${text}`;
    toast(text, 'error');
    this.poller.poke();
    return this.lastError;
  }

  // ---- requests ----

  private async refresh(): Promise<void> {
    const startedAt = performance.now();
    try {
      const body = parseOperatorBody(await this.api.operator());
      this.supported = true;
      if (body) this.learn(body.holder, startedAt);
      else this.update();
    } catch (error) {
      if (error instanceof ApiError && error.status === 404) {
        // A server without the lock: no card, nothing refused here.
        this.supported = false;
        this.poller.stop();
        this.setHolder(null);
      }
      // Unreachable or 5xx: keep what we knew; the next poll asks again.
    }
  }

  /** A holder from an answer to a request started at `startedAt`: learn who this page is from it. */
  private learn(holder: OperatorHolder | null, startedAt: number): void {
    if (holder && this.me === null) {
      if (this.claimedAt > 0 && startedAt >= this.claimedAt) this.me = holder.tokenId;
      else if (this.refusedAt > 0 && startedAt >= this.refusedAt) this.notMe.add(holder.tokenId);
    }
    if (startedAt >= this.claimedAt) this.claimedAt = 0;
    if (startedAt >= this.refusedAt) this.refusedAt = 0;
    this.setHolder(holder);
  }

  private async takeOver(): Promise<void> {
    const holder = this.holder;
    if (holder && !window.confirm(takeOverPrompt(holder))) return;
    await this.act('take_over');
  }

  private async act(action: OperatorAction): Promise<void> {
    if (this.busy) return;
    this.busy = true;
    this.showError(null);
    this.render();
    try {
      const body = parseOperatorBody(await this.api.operatorAction(action));
      // The reply is the state after the change: no GET needed before the next period.
      this.poller.fresh();
      if (body) {
        // Acquired or taken over: the holder is this page's token.
        if (body.holder && action !== 'release') this.me = body.holder.tokenId;
        this.setHolder(body.holder);
      } else {
        this.poller.poke();
      }
      toast(action === 'release' ? 'Control released: nobody drives' : 'You drive the robot now', action === 'release' ? 'info' : 'ok');
    } catch (error) {
      this.showError(operatorErrorText(error, action));
      toast(operatorErrorText(error, action), 'error');
      // operator_busy asks again through the API observer; anything else may have changed too.
      this.poller.poke();
    } finally {
      this.busy = false;
      this.render();
    }
  }

  // ---- state ----

  private setHolder(holder: OperatorHolder | null | undefined): void {
    const before = this.view.state;
    this.holder = holder;
    const after = this.computeView().state;
    // "X took over from you" holds while X drives.
    if (after === 'mine' || after === 'free' || (holder && this.lostTo !== holderName(holder))) this.lostTo = null;
    if (before === 'mine' && after === 'other' && holder) {
      this.lostTo = holderName(holder);
      toast(`${this.lostTo} took over: you no longer drive the robot`, 'error');
    }
    this.update();
  }

  private computeView(): OperatorView {
    return operatorView({ supported: this.supported, holder: this.holder, identity: { me: this.me, notMe: this.notMe }, admin: this.admin });
  }

  private update(): void {
    const previous = this.view;
    this.view = this.computeView();
    this.render();
    if (previous.blocksCommands !== this.view.blocksCommands || previous.lockedReason !== this.view.lockedReason || previous.state !== this.view.state) {
      this.hooks.changed(this.view);
    }
  }

  private showError(message: string | null): void {
    this.lastError = message;
    const box = byId('operator-error');
    box.hidden = !message;
    box.textContent = message ?? '';
  }

  private render(): void {
    const view = this.view;
    byId('operator-panel').hidden = view.state === 'unsupported';
    const line = byId('operator-holder');
    line.textContent = view.line;
    line.title = view.title;
    line.dataset.state = view.state;
    const show = (id: string, shown: boolean) => {
      const button = byId<HTMLButtonElement>(id);
      button.hidden = !shown;
      button.disabled = this.busy;
    };
    show('operator-acquire', view.buttons.acquire);
    show('operator-release', view.buttons.release);
    show('operator-take-over', view.buttons.takeOver);
    // No empty row under the line when there is nothing to press.
    byId('operator-buttons').hidden = !view.buttons.acquire && !view.buttons.release && !view.buttons.takeOver;
    if (this.holder) byId('operator-take-over').title = `Take the lock from ${holderName(this.holder)} (admin; POST /api/v1/operator {action: take_over})`;
    byId('operator-acquire').title =
      view.state === 'held' && this.holder
        ? `This page cannot tell yet whether ${holderName(this.holder)} is its own token: Take control keeps the lock if so, and is refused (operator_busy) if not`
        : 'Take the operator lock: nobody else can drive until you release it (POST /api/v1/operator {action: acquire})';
    const note = byId('operator-note');
    const lost = this.lostTo && view.state === 'other' ? `${this.lostTo} took over from you. ` : '';
    note.hidden = !view.note;
    note.textContent = view.note ? `${lost}${view.note}` : '';
  }
}
