// The Maps page: list, import (PGM/PNG + ROS map_server parameters), activate, delete, downloads
// and thumbnails (fetched with the bearer header, shown through object URLs).

import { errorText } from '../apierror';
import type { ApiClient, MapInfo } from '../api';
import { dateTime, fmt, h, saveBlob, toast, toBase64 } from '../ui';

export class MapsPage {
  private readonly list: HTMLElement;
  private readonly error: HTMLElement;
  private thumbnails: string[] = [];
  private loading = false;

  constructor(
    root: HTMLElement,
    private readonly api: ApiClient,
  ) {
    this.list = h('div', { class: 'map-grid', testid: 'maps-list' });
    this.error = h('div', { class: 'page-error', testid: 'maps-error' });
    this.error.hidden = true;
    root.append(
      h(
        'div',
        { class: 'page-head' },
        h('h1', { text: 'Maps' }),
        h('div', { class: 'spacer' }),
        h('button', { class: 'btn', testid: 'maps-refresh', text: 'Refresh', on: { click: () => void this.refresh() } }),
      ),
      this.error,
      h('div', { class: 'maps-layout' }, this.list, this.importForm()),
    );
  }

  async refresh(): Promise<void> {
    if (this.loading) return;
    this.loading = true;
    try {
      const maps = await this.api.maps();
      this.error.hidden = true;
      this.render(maps);
    } catch (error) {
      this.showError(`Could not list the maps: ${errorText(error)}`);
    } finally {
      this.loading = false;
    }
  }

  private showError(message: string): void {
    this.error.textContent = message;
    this.error.hidden = false;
  }

  private render(maps: MapInfo[]): void {
    for (const url of this.thumbnails) URL.revokeObjectURL(url);
    this.thumbnails = [];
    if (maps.length === 0) {
      this.list.replaceChildren(h('div', { class: 'empty', text: 'No stored maps yet. Import one, or build one with mapping.' }));
      return;
    }
    const sorted = [...maps].sort((a, b) => Number(b.active) - Number(a.active) || b.id - a.id);
    this.list.replaceChildren(...sorted.map((map) => this.card(map)));
  }

  private card(map: MapInfo): HTMLElement {
    const thumb = h('div', { class: 'thumb' }, h('span', { class: 'muted', text: 'loading…' }));
    void this.api
      .blob(`/api/v1/maps/${map.id}/image`)
      .then((blob) => {
        const url = URL.createObjectURL(blob);
        this.thumbnails.push(url);
        thumb.replaceChildren(h('img', { attrs: { src: url, alt: `map ${map.name}` } }));
      })
      .catch((error) => thumb.replaceChildren(h('span', { class: 'muted', text: errorText(error) })));

    const download = (what: string, filename: string) => async () => {
      try {
        saveBlob(await this.api.blob(`/api/v1/maps/${map.id}/${what}`), filename);
      } catch (error) {
        toast(`Download failed: ${errorText(error)}`, 'error');
      }
    };
    const base = slug(map.name) || `map-${map.id}`;
    return h(
      'article',
      { class: `map-card${map.active ? ' active' : ''}`, testid: 'map-item', attrs: { 'data-map-id': String(map.id) } },
      thumb,
      h(
        'div',
        { class: 'map-info' },
        h('div', { class: 'map-title' }, h('strong', { text: map.name }), map.active ? h('span', { class: 'badge good', text: 'active' }) : null),
        h('div', { class: 'muted small', text: `#${map.id} · ${map.width}×${map.height} cells · ${fmt(map.resolution, 3)} m/cell` }),
        h('div', { class: 'muted small', text: `${fmt(map.width * map.resolution, 1)} × ${fmt(map.height * map.resolution, 1)} m · origin (${fmt(map.origin.x)}, ${fmt(map.origin.y)}, ${fmt(map.origin.theta)})` }),
        h('div', { class: 'muted small', text: `created ${dateTime(map.created)}` }),
        h(
          'div',
          { class: 'actions' },
          h('button', {
            class: 'btn small primary',
            testid: 'map-activate',
            text: map.active ? 'Active' : 'Activate',
            attrs: map.active ? { disabled: '' } : {},
            on: { click: () => void this.activate(map) },
          }),
          h('button', { class: 'btn small danger', testid: 'map-delete', text: 'Delete', on: { click: () => void this.remove(map) } }),
          h('span', { class: 'spacer' }),
          h('button', { class: 'btn small ghost', text: 'PGM', title: 'ROS map_server image', on: { click: download('map.pgm', `${base}.pgm`) } }),
          h('button', { class: 'btn small ghost', text: 'YAML', title: 'ROS map_server metadata', on: { click: download('map.yaml', `${base}.yaml`) } }),
          h('button', { class: 'btn small ghost', text: 'PNG', on: { click: download('image', `${base}.png`) } }),
        ),
      ),
    );
  }

  private async activate(map: MapInfo): Promise<void> {
    try {
      await this.api.activateMap(map.id);
      toast(`Map "${map.name}" is active`, 'ok');
    } catch (error) {
      toast(`Could not activate "${map.name}": ${errorText(error)}`, 'error');
    }
    await this.refresh();
  }

  private async remove(map: MapInfo): Promise<void> {
    if (!window.confirm(`Delete map "${map.name}" (#${map.id})?`)) return;
    try {
      await this.api.deleteMap(map.id);
      toast(`Map "${map.name}" deleted`, 'ok');
    } catch (error) {
      // 409 map_active: the server refuses to delete the active map.
      toast(`Could not delete "${map.name}": ${errorText(error)}`, 'error');
    }
    await this.refresh();
  }

  private importForm(): HTMLElement {
    const file = h('input', { testid: 'import-file', attrs: { type: 'file', accept: '.pgm,.png,image/png,image/x-portable-graymap', required: '' } });
    const name = h('input', { testid: 'import-name', attrs: { type: 'text', placeholder: 'name', required: '', maxlength: '128' } });
    const resolution = numberInput('import-resolution', '0.05', '0.001');
    const originX = numberInput('import-origin-x', '0', 'any');
    const originY = numberInput('import-origin-y', '0', 'any');
    const originTheta = numberInput('import-origin-theta', '0', 'any');
    const negate = h('input', { testid: 'import-negate', attrs: { type: 'checkbox' } });
    const occupied = numberInput('import-occupied', '0.65', '0.01');
    const free = numberInput('import-free', '0.196', '0.001');
    const submit = h('button', { class: 'btn primary', testid: 'import-submit', text: 'Import', attrs: { type: 'submit' } });
    const status = h('div', { class: 'small muted', testid: 'import-status' });

    file.addEventListener('change', () => {
      const chosen = file.files?.[0];
      if (chosen && !name.value) name.value = chosen.name.replace(/\.(pgm|png)$/i, '');
    });

    const form = h(
      'form',
      { class: 'card import', testid: 'import-form' },
      h('h2', { text: 'Import a map' }),
      h('p', { class: 'muted small', text: 'A PGM or PNG occupancy image with ROS map_server parameters.' }),
      field('image', file),
      field('name', name),
      field('resolution (m/cell)', resolution),
      h('div', { class: 'row3' }, field('origin x (m)', originX), field('origin y (m)', originY), field('origin θ (rad)', originTheta)),
      h('div', { class: 'row3' }, field('occupied thresh', occupied), field('free thresh', free), field('negate', negate)),
      h('div', { class: 'actions' }, submit, status),
    );
    form.addEventListener('submit', (e) => {
      e.preventDefault();
      void (async () => {
        const chosen = file.files?.[0];
        if (!chosen) {
          status.textContent = 'Choose an image first.';
          return;
        }
        submit.disabled = true;
        status.textContent = 'Uploading…';
        try {
          const bytes = new Uint8Array(await chosen.arrayBuffer());
          const { id } = await this.api.importMap({
            name: name.value.trim(),
            resolution: Number(resolution.value),
            origin: { x: Number(originX.value), y: Number(originY.value), theta: Number(originTheta.value) },
            image_base64: toBase64(bytes),
            negate: negate.checked,
            occupied_thresh: Number(occupied.value),
            free_thresh: Number(free.value),
          });
          status.textContent = `Imported as #${id}.`;
          toast(`Map "${name.value}" imported (#${id})`, 'ok');
          form.reset();
          await this.refresh();
        } catch (error) {
          status.textContent = errorText(error);
          toast(`Import failed: ${errorText(error)}`, 'error');
        } finally {
          submit.disabled = false;
        }
      })();
    });
    return form;
  }
}

function numberInput(testid: string, value: string, step: string): HTMLInputElement {
  const input = h('input', { testid, attrs: { type: 'number', step, required: '' } });
  input.defaultValue = value;
  input.value = value;
  return input;
}

function field(label: string, input: HTMLElement): HTMLElement {
  return h('label', { class: 'field' }, h('span', { text: label }), input);
}

function slug(name: string): string {
  return name
    .toLowerCase()
    .replace(/[^a-z0-9]+/g, '-')
    .replace(/^-|-$/g, '');
}
