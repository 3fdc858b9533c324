// The "Connected" card of the Live page, for admins: every open connection of mobotd (GET
// /api/v1/clients): kind, label, role, address, topics, data sent, frames dropped. The same
// request tells the page whether its token is an admin (200) or not (403: the card stays hidden),
// which the Operator card needs for Take over. Collapsed by default; refreshed every 3 s while
// open on the Live page and connected. The logic is clients.ts; this renders it.

import { errorText } from './apierror';
import type { ApiClient } from './api';
import { bytesText, clientsAccess, clientsSummary, clientWho, parseClients, topicsText } from './clients';
import type { ClientInfo } from './clients';
import { Poller } from './poller';
import { byId, dateTime, fmt, h } from './ui';

export const CLIENTS_POLL_MS = 3000;

export interface ClientsPanelHooks {
  /** Whether this page's token is an admin: true (200), false (403), null (not known). */
  admin(admin: boolean | null): void;
}

export class ClientsPanel {
  /** The token may list the connections (the card is shown). */
  admin: boolean | null = null;
  clients: ClientInfo[] = [];
  lastError: string | null = null;
  private readonly card: HTMLDetailsElement;
  private readonly poller: Poller;
  private visible = true;
  private online = false;

  constructor(
    private readonly api: ApiClient,
    private readonly hooks: ClientsPanelHooks,
  ) {
    this.card = byId<HTMLDetailsElement>('clients-panel');
    this.poller = new Poller(() => this.refresh(), { periodMs: CLIENTS_POLL_MS, minGapMs: 1000 });
    this.card.addEventListener('toggle', () => this.sync());
    this.render();
  }

  /** The card is open and its list refreshes. */
  get polling(): boolean {
    return this.poller.active;
  }

  /** GET /clients requests started while open. */
  get polls(): number {
    return this.poller.runs;
  }

  get open(): boolean {
    return this.card.open;
  }

  /** On (re)connect: is this token an admin? (one GET; the list itself waits for the card to open). */
  async connected(): Promise<void> {
    this.online = true;
    // An open card's first refresh answers both; otherwise one GET says whether this is an admin.
    if (!this.wanted()) await this.refresh();
    this.sync();
  }

  disconnected(): void {
    this.online = false;
    this.sync();
  }

  /** Another token: whether it is an admin is asked again on connect. */
  tokenChanged(): void {
    this.setAdmin(null);
    this.clients = [];
    this.render();
  }

  /** The Live page is shown (the list only refreshes there). */
  setVisible(visible: boolean): void {
    this.visible = visible;
    this.sync();
  }

  private wanted(): boolean {
    return this.online && this.visible && this.admin === true && this.card.open;
  }

  private sync(): void {
    const wanted = this.wanted();
    if (wanted && !this.poller.active) this.poller.start();
    else if (!wanted && this.poller.active) this.poller.stop();
  }

  private async refresh(): Promise<void> {
    try {
      const list = parseClients(await this.api.clients());
      this.setAdmin(true);
      if (list) this.clients = list;
      this.lastError = list ? null : 'GET /api/v1/clients answered something else than a list';
    } catch (error) {
      const access = clientsAccess(error);
      // 404: a server without the list, which says nothing of the token's role.
      if (access === 'not_admin') this.setAdmin(false);
      if (access === 'absent') this.setAdmin(null);
      this.lastError = access === 'unknown' ? errorText(error) : null;
    }
    this.render();
    this.sync();
  }

  private setAdmin(admin: boolean | null): void {
    if (admin === this.admin) return;
    this.admin = admin;
    this.hooks.admin(admin);
  }

  private render(): void {
    this.card.hidden = this.admin !== true;
    byId('clients-count').textContent = this.clients.length ? clientsSummary(this.clients) : '';
    const error = byId('clients-error');
    error.hidden = !this.lastError;
    error.textContent = this.lastError ?? '';
    const list = byId('client-list');
    if (this.clients.length === 0) {
      list.replaceChildren(h('li', { class: 'empty small', text: 'No connections listed yet.' }));
      return;
    }
    list.replaceChildren(...this.clients.map((c) => this.row(c)));
  }

  private row(c: ClientInfo): HTMLElement {
    const topics = topicsText(c);
    const where = c.rttMs !== null ? `${c.address} · rtt ${fmt(c.rttMs, 1)} ms` : c.address;
    return h(
      'li',
      {
        class: 'client-item',
        testid: 'client-item',
        title: `connection #${c.id}${c.since !== null ? `, open since ${dateTime(c.since)}` : ''}${c.topics.length ? `\ntopics: ${c.topics.join(', ')}` : ''}`,
        attrs: { 'data-kind': c.kind, 'data-label': c.label ?? '', 'data-id': String(c.id) },
      },
      h(
        'div',
        { class: 'client-head' },
        h('span', { class: 'badge', testid: 'client-kind', text: c.kind }),
        h('span', { class: 'client-who', testid: 'client-label', text: clientWho(c) }),
        c.role ? h('span', { class: 'muted small', testid: 'client-role', text: c.role }) : null,
        h('span', { class: 'spacer' }),
        h('span', { class: 'mono', title: 'data sent', testid: 'client-sent', text: bytesText(c.bytesSent) }),
      ),
      h(
        'div',
        { class: 'client-detail mono small muted' },
        h('span', { class: 'client-address', testid: 'client-address', text: where }),
        h('span', { class: `client-dropped${c.dropped > 0 ? ' warn' : ''}`, testid: 'client-dropped', text: `${c.dropped} dropped` }),
      ),
      topics ? h('div', { class: 'client-topics mono small muted', testid: 'client-topics', text: topics }) : null,
    );
  }
}
