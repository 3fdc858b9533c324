// Keep-out zones of a stored map (GET/POST /api/v1/maps/{id}/zones, DELETE .../zones/{zid}): the
// zone bodies and what a refusal means. Pure, unit-tested.

import { ApiError, errorText } from './apierror';
import { polygonArea } from './polygon';

export interface Zone {
  id: number;
  name: string;
  /** Map frame vertices. */
  polygon: [number, number][];
}

export interface ZoneRequest {
  name?: string;
  polygon: [number, number][];
}

/** A GET /zones body, keeping the well-formed zones. */
export function parseZones(value: unknown): Zone[] {
  if (!Array.isArray(value)) return [];
  const zones: Zone[] = [];
  for (const item of value) {
    const z = item as { id?: unknown; name?: unknown; polygon?: unknown };
    if (!z || typeof z.id !== 'number' || !Array.isArray(z.polygon)) continue;
    const polygon: [number, number][] = [];
    for (const p of z.polygon) {
      if (Array.isArray(p) && typeof p[0] === 'number' && typeof p[1] === 'number' && Number.isFinite(p[0]) && Number.isFinite(p[1])) polygon.push([p[0], p[1]]);
    }
    if (polygon.length < 3) continue;
    zones.push({ id: z.id, name: typeof z.name === 'string' ? z.name : '', polygon });
  }
  return zones.sort((a, b) => a.id - b.id);
}

/** The request body: vertices rounded to the millimetre, the name only when one was given. */
export function zoneRequest(polygon: readonly (readonly [number, number])[], name: string): ZoneRequest {
  const body: ZoneRequest = { polygon: polygon.map(([x, y]) => [round3(x), round3(y)]) };
  if (name.trim()) body.name = name.trim();
  return body;
}

/** "Zone 3 · 4 vertices · 2.25 m²". */
export function zoneSummary(zone: Zone): string {
  const area = polygonArea(zone.polygon);
  return `${zone.polygon.length} vertices · ${area < 10 ? area.toFixed(2) : area.toFixed(1)} m²`;
}

/** The message shown for a refused zone request; invalid_polygon shows the server's own words. */
export function zoneErrorText(error: unknown): string {
  if (error instanceof ApiError) {
    switch (error.code) {
      case 'invalid_polygon':
        return `The server refused the polygon: ${error.message} (invalid_polygon)`;
      case 'forbidden':
        return 'This token may not change keep-out zones.';
      case 'unknown_map':
        return 'The map is no longer stored (unknown_map).';
      default:
        if (error.status === 404 && error.code === 'not_found') return 'This server has no keep-out zones.';
        return error.describe();
    }
  }
  return errorText(error);
}

function round3(x: number): number {
  return Math.round(x * 1000) / 1000;
}
