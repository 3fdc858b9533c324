// The connections of mobotd as GET /api/v1/clients (admin only) lists them: parsing the body
// defensively, the order they are shown in, and how their numbers read. Pure, unit-tested;
// clients_panel.ts renders them.

import { ApiError } from './apierror';

export interface ClientInfo {
  id: number;
  /** `http` or `stream` (another word from a newer server is shown as it is). */
  kind: string;
  /** null on an HTTP connection that has not authenticated yet. */
  role: string | null;
  label: string | null;
  address: string;
  /** Unix seconds. */
  since: number | null;
  rttMs: number | null;
  /** A stream's subscribed topics (none for HTTP). */
  topics: string[];
  bytesSent: number;
  dropped: number;
}

const finite = (x: unknown): x is number => typeof x === 'number' && Number.isFinite(x);
const text = (x: unknown): string | null => (typeof x === 'string' && x.trim() !== '' ? x.trim() : null);
const count = (x: unknown): number => (finite(x) && x >= 0 ? x : 0);

/** One row; null when it has no id or kind. */
export function parseClient(value: unknown): ClientInfo | null {
  if (!value || typeof value !== 'object' || Array.isArray(value)) return null;
  const v = value as Record<string, unknown>;
  const kind = text(v.kind);
  if (!finite(v.id) || !kind) return null;
  return {
    id: v.id,
    kind,
    role: text(v.role),
    label: text(v.label),
    address: text(v.address) ?? '?',
    since: finite(v.since) && v.since > 0 ? v.since : null,
    rttMs: finite(v.rtt_ms) && v.rtt_ms >= 0 ? v.rtt_ms : null,
    topics: Array.isArray(v.topics) ? v.topics.filter((t): t is string => typeof t === 'string') : [],
    bytesSent: count(v.bytes_sent),
    dropped: count(v.dropped),
  };
}

/** The list, streams first (the people watching), then by id; malformed rows dropped; null when the body is not a list. */
export function parseClients(value: unknown): ClientInfo[] | null {
  if (!Array.isArray(value)) return null;
  return value
    .map(parseClient)
    .filter((c): c is ClientInfo => c !== null)
    .sort((a, b) => Number(b.kind === 'stream') - Number(a.kind === 'stream') || a.id - b.id);
}

/** Who the connection is: its token's label, else its role, else that it has not authenticated. */
export function clientWho(client: ClientInfo): string {
  return client.label ?? (client.role ? `(${client.role})` : 'not authenticated');
}

/** Bytes for people: "512 B", "1.5 kB", "12.3 MB", "1.20 GB". */
export function bytesText(bytes: number): string {
  if (!finite(bytes) || bytes < 0) return '–';
  if (bytes < 1000) return `${Math.round(bytes)} B`;
  if (bytes < 1e6) return `${(bytes / 1e3).toFixed(1)} kB`;
  if (bytes < 1e9) return `${(bytes / 1e6).toFixed(1)} MB`;
  return `${(bytes / 1e9).toFixed(2)} GB`;
}

/** "pose, scan, map +9"; "no topics" for a stream without any; "" for HTTP. */
export function topicsText(client: ClientInfo, shown = 3): string {
  if (client.kind !== 'stream') return '';
  if (client.topics.length === 0) return 'no topics';
  const head = client.topics.slice(0, shown).join(', ');
  const rest = client.topics.length - shown;
  return rest > 0 ? `${head} +${rest}` : head;
}

/** "2 streams · 5 http" for the card's heading. */
export function clientsSummary(clients: readonly ClientInfo[]): string {
  const streams = clients.filter((c) => c.kind === 'stream').length;
  const other = clients.length - streams;
  return `${streams} stream${streams === 1 ? '' : 's'} · ${other} http`;
}

/**
 * What a GET /api/v1/clients outcome says about this page's token: admin (200), not admin (403;
 * the list is hidden), absent (404: a server without the list), unknown (unreachable, 5xx).
 */
export type ClientsAccess = 'admin' | 'not_admin' | 'absent' | 'unknown';

export function clientsAccess(error: unknown): ClientsAccess {
  if (!(error instanceof ApiError)) return 'unknown';
  if (error.status === 403) return 'not_admin';
  if (error.status === 404) return 'absent';
  return 'unknown';
}
