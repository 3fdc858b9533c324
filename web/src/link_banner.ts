// The banner across the top while the stream is down: the robot stops by itself (its teleop lease
// runs out), the page is trying again, which attempt, and when the next one goes. Gone once the
// stream is back. The words are pure (bannerView, unit-tested); LinkBanner renders them.

import type { ConnectionState } from './stream';

export interface BannerInput {
  state: ConnectionState;
  /** The stream was open at least once since sign-in (else: never reached yet). */
  everConnected: boolean;
  /** Reconnect attempts since the stream was last open. */
  attempt: number;
  /** Until the next attempt; null while one is under way. */
  nextInMs: number | null;
  /** Why the last connection ended ("stalled: no data for 2 s", "closed (1006)"). */
  reason: string;
  /** The teleop lease the page sends with each command. */
  leaseMs: number;
}

export interface BannerView {
  shown: boolean;
  title: string;
  detail: string;
}

const HIDDEN: BannerView = { shown: false, title: '', detail: '' };

export function bannerView(input: BannerInput): BannerView {
  // Signed out, refused (the login view says why) or connected: nothing to say here.
  if (input.state === 'connected' || input.state === 'auth_error') return HIDDEN;
  // The first connection of a sign-in is still being made: not an outage yet.
  if (!input.everConnected && input.attempt === 0) return HIDDEN;
  const title = input.everConnected
    ? `Connection lost — the robot stops by itself within its teleop lease (${input.leaseMs} ms); reconnecting…`
    : 'Cannot reach the robot — reconnecting…';
  const parts = [`attempt ${Math.max(1, input.attempt)}`];
  parts.push(input.nextInMs === null || input.state === 'connecting' ? 'connecting now' : `next in ${(Math.max(0, input.nextInMs) / 1000).toFixed(1)} s`);
  if (input.reason && input.reason !== 'stopped') parts.push(input.reason);
  return { shown: true, title, detail: parts.join(' · ') };
}

/** The banner element (index.html #link-banner). */
export class LinkBanner {
  view: BannerView = HIDDEN;

  constructor(
    private readonly root: HTMLElement,
    private readonly titleEl: HTMLElement,
    private readonly detailEl: HTMLElement,
  ) {}

  render(view: BannerView): void {
    this.view = view;
    this.root.hidden = !view.shown;
    document.body.classList.toggle('link-lost', view.shown);
    if (!view.shown) return;
    if (this.titleEl.textContent !== view.title) this.titleEl.textContent = view.title;
    if (this.detailEl.textContent !== view.detail) this.detailEl.textContent = view.detail;
  }
}
