// The Keep-out zones card of the Live page and its draw mode on the map: "Draw zone" (or K), click
// the vertices, double-click, Enter or a click on the first vertex closes, Backspace takes a vertex
// back, Esc cancels. The closed polygon goes to POST /api/v1/maps/{id}/zones of the map shown; a
// refusal (400 invalid_polygon) shows the server's message and leaves the polygon open to mend.
// The list (GET .../zones, on connect and when another map is shown) has a Delete per zone; the
// zones are drawn hatched (layers/keepout_zones.ts), the draft by layers/polygon_draft.ts.

import type { ApiClient, PathPresence } from './api';
import type { MapGrid } from './frames';
import type { MapTool } from './map/input';
import type { MapView } from './map/mapview';
import { PolygonDraft } from './polygon_tool';
import { isTypingTarget } from './teleop';
import { byId, h, toast } from './ui';
import { parseZones, zoneErrorText, zoneRequest, zoneSummary } from './zones';
import type { Zone } from './zones';

/** Clicks this many screen pixels from the first vertex close the polygon; from the last, they are ignored. */
const CLICK_TOLERANCE_PX = 7;
const TOOL_COLOR = '#f59e0b';

export interface ZonesPanelHooks {
  /** Another map tool (goal, obstacle, pose) gives way before drawing starts. */
  leaveOtherTools(): void;
}

export class ZonesPanel {
  readonly draft = new PolygonDraft();
  zones: Zone[] = [];
  /** The stored map whose zones are listed (null: none shown, or not a stored one). */
  mapId: number | null = null;
  lastError: string | null = null;
  /** Whether keyboard shortcuts apply (the Live page is shown). */
  enabled = true;
  private presence: PathPresence = 'unknown';
  private loading: number | null = null;

  constructor(
    private readonly api: ApiClient,
    private readonly mapView: MapView,
    private readonly hooks: ZonesPanelHooks,
  ) {
    mapView.layers.polygonDraft.attach(this.draft);
    byId('zone-draw').addEventListener('click', () => this.toggle());
    byId('zone-mode-cancel').addEventListener('click', () => this.stop());
    window.addEventListener('keydown', (e) => this.onKey(e));
    this.render();
  }

  get drawing(): boolean {
    return this.draft.state !== 'idle';
  }

  // ---- map and connection ----

  /** A whole map arrived: list its zones when it is another stored map. */
  onMap(map: MapGrid): void {
    const id = map.id > 0 ? map.id : null;
    if (id === this.mapId) return;
    this.mapId = id;
    this.zones = [];
    this.stop();
    void this.load();
  }

  /** On (re)connect: the zones of the map shown. */
  async connected(): Promise<void> {
    await this.load();
  }

  async load(): Promise<void> {
    const id = this.mapId;
    if (id === null) {
      this.render();
      return;
    }
    if (this.loading === id) return;
    this.loading = id;
    try {
      const zones = parseZones(await this.api.zones(id));
      if (id !== this.mapId) return;
      this.presence = 'present';
      this.zones = zones;
    } catch (error) {
      if (id !== this.mapId) return;
      const text = zoneErrorText(error);
      if (/no keep-out zones/.test(text)) this.presence = 'absent';
      else this.showError(`Could not list the zones: ${text}`, false);
      this.zones = [];
    } finally {
      if (this.loading === id) this.loading = null;
      this.render();
    }
  }

  // ---- drawing ----

  toggle(): void {
    if (this.drawing) this.stop();
    else this.start();
  }

  start(): void {
    if (this.presence === 'absent' || this.mapId === null) {
      this.showError(this.mapId === null ? 'Zones belong to a stored map: none is shown.' : 'This server has no keep-out zones.');
      return;
    }
    this.hooks.leaveOtherTools();
    this.showError(null);
    this.draft.start();
    this.mapView.setTool(this.tool());
    this.render();
  }

  /** Leaves the draw mode, dropping the draft. */
  stop(): void {
    const had = this.drawing;
    this.draft.cancel();
    if (had && this.mapView.activeTool === 'zone') this.mapView.setTool(null);
    this.render();
  }

  private tool(): MapTool {
    return {
      name: 'zone',
      color: TOOL_COLOR,
      heading: false,
      ownPreview: true,
      done: (p) => this.onResult(this.draft.click([p.x, p.y], CLICK_TOLERANCE_PX / this.mapView.view.scale)),
      doubleClick: () => this.onResult(this.draft.close()),
      moved: (p) => {
        this.draft.move([p.x, p.y]);
        this.renderBanner();
      },
      // Another tool took over (G, O, P, leaving the page): the draft goes.
      left: () => {
        this.draft.cancel();
        this.render();
      },
    };
  }

  private onKey(e: KeyboardEvent): void {
    if (!this.enabled || e.ctrlKey || e.metaKey || e.altKey) return;
    if (!byId('login').hidden) return;
    const key = e.key.toLowerCase();
    const inName = e.target === byId('zone-name');
    if (this.draft.active && key === 'enter' && (inName || !isTypingTarget(e.target))) {
      e.preventDefault();
      this.onResult(this.draft.close());
      return;
    }
    if (isTypingTarget(e.target) || e.repeat) return;
    if (key === 'escape' && this.drawing) {
      e.preventDefault();
      this.stop();
    } else if (key === 'backspace' && this.draft.active) {
      e.preventDefault();
      this.draft.undo();
      this.render();
    } else if (key === 'k') {
      e.preventDefault();
      this.toggle();
    }
  }

  private onResult(result: ReturnType<PolygonDraft['click']>): void {
    if (result.kind === 'refused') this.showError(result.reason);
    else if (result.kind === 'added') this.showError(null);
    else if (result.kind === 'closed') void this.submit(result.polygon);
    this.render();
  }

  private async submit(polygon: [number, number][]): Promise<void> {
    const mapId = this.mapId;
    if (mapId === null) {
      this.draft.reopen();
      this.showError('Zones belong to a stored map: none is shown.');
      return;
    }
    const nameInput = byId<HTMLInputElement>('zone-name');
    try {
      const reply = await this.api.addZone(mapId, zoneRequest(polygon, nameInput.value));
      this.draft.accepted();
      nameInput.value = '';
      this.showError(null);
      if (this.mapView.activeTool === 'zone') this.mapView.setTool(null);
      toast(`Keep-out zone #${reply.id} stored (${polygon.length} vertices)`, 'ok');
      await this.load();
    } catch (error) {
      // Refused (invalid_polygon): the server's words, and the polygon stays open to mend.
      this.draft.reopen();
      this.showError(zoneErrorText(error));
    } finally {
      this.render();
    }
  }

  async remove(zone: Zone): Promise<void> {
    const mapId = this.mapId;
    if (mapId === null) return;
    try {
      await this.api.deleteZone(mapId, zone.id);
      toast(`Keep-out zone #${zone.id} deleted`, 'ok');
    } catch (error) {
      this.showError(`Could not delete zone #${zone.id}: ${zoneErrorText(error)}`);
    }
    await this.load();
  }

  // ---- rendering ----

  private showError(message: string | null, withToast = true): void {
    this.lastError = message;
    const box = byId('zone-error');
    box.hidden = !message;
    box.textContent = message ?? '';
    if (message && withToast) toast(message, 'error');
  }

  private renderBanner(): void {
    const banner = byId('zone-mode');
    banner.hidden = !this.drawing;
    if (!this.drawing) return;
    const n = this.draft.vertices.length;
    const problem = n >= 3 ? this.draft.problem : null;
    byId('zone-mode-problem').textContent =
      this.draft.state === 'submitting' ? 'sending…' : problem ? `${n} vertices · ${problem}` : `${n} vert${n === 1 ? 'ex' : 'ices'}`;
    this.mapView.invalidate();
  }

  render(): void {
    this.mapView.layers.zones.set(this.zones);
    const button = byId<HTMLButtonElement>('zone-draw');
    button.classList.toggle('active', this.drawing);
    button.setAttribute('aria-pressed', String(this.drawing));
    button.disabled = this.presence === 'absent' || this.mapId === null;
    button.title =
      this.presence === 'absent'
        ? 'This server has no keep-out zones'
        : 'Draw a keep-out zone (K): click the vertices on the map, double-click or Enter to close, Backspace takes a vertex back, Esc cancels';
    byId('zones-map').textContent = this.presence === 'absent' ? 'not on this server' : this.mapId !== null ? `map #${this.mapId}` : '';
    this.renderBanner();
    const list = byId('zone-list');
    if (this.zones.length === 0) {
      list.replaceChildren(h('li', { class: 'empty small muted', text: this.presence === 'absent' ? 'This server has no keep-out zones.' : 'No keep-out zones: press K and click the map.' }));
      return;
    }
    list.replaceChildren(
      ...this.zones.map((zone) =>
        h(
          'li',
          { class: 'zone-item', testid: 'zone-item', attrs: { 'data-id': String(zone.id) } },
          h('span', { class: 'sw sw-zone' }),
          h('span', { class: 'mono', text: `#${zone.id}` }),
          h('span', { class: 'name', title: zone.name, text: zone.name || '' }),
          h('span', { class: 'mono muted', text: zoneSummary(zone) }),
          h('button', {
            class: 'btn small ghost',
            testid: 'zone-delete',
            title: `Delete zone #${zone.id} (DELETE /api/v1/maps/${this.mapId}/zones/${zone.id})`,
            text: 'Delete',
            on: { click: () => void this.remove(zone) },
          }),
        ),
      ),
    );
  }
}
