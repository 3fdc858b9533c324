import { describe, expect, it } from 'vitest';
import { ApiError } from '../src/apierror';
import { bytesText, clientsAccess, clientsSummary, clientWho, parseClient, parseClients, topicsText } from '../src/clients';

const STREAM = { id: 16, kind: 'stream', role: 'operator', label: 'bob', address: '127.0.0.1:34038', since: 1796441490.3, rtt_ms: 2.5, topics: ['pose', 'scan', 'map', 'status'], bytes_sent: 2036, dropped: 3 };
const HTTP = { id: 17, kind: 'http', role: 'admin', label: 'admin (--token)', address: '127.0.0.1:34044', since: 1796441491.3, bytes_sent: 0, dropped: 0 };
const ANONYMOUS = { id: 12, kind: 'http', role: null, label: null, address: '10.0.0.9:5000', since: 1796441480, bytes_sent: 0, dropped: 0 };

describe('GET /clients bodies', () => {
  it('parses a stream and an HTTP connection', () => {
    expect(parseClient(STREAM)).toEqual({
      id: 16, kind: 'stream', role: 'operator', label: 'bob', address: '127.0.0.1:34038', since: 1796441490.3, rttMs: 2.5,
      topics: ['pose', 'scan', 'map', 'status'], bytesSent: 2036, dropped: 3,
    });
    expect(parseClient(HTTP)).toMatchObject({ kind: 'http', rttMs: null, topics: [], bytesSent: 0 });
  });

  it('keeps a connection that has not authenticated (role and label null)', () => {
    const c = parseClient(ANONYMOUS)!;
    expect(c.role).toBeNull();
    expect(c.label).toBeNull();
    expect(clientWho(c)).toBe('not authenticated');
    expect(clientWho({ ...c, role: 'viewer' })).toBe('(viewer)');
    expect(clientWho(parseClient(STREAM)!)).toBe('bob');
  });

  it('reads odd fields as unknown, drops rows without id or kind, and a body that is no list', () => {
    expect(parseClient({ id: 1, kind: 'stream', topics: ['pose', 3, null], bytes_sent: -5, dropped: 'many', rtt_ms: -1 })).toMatchObject({
      address: '?', topics: ['pose'], bytesSent: 0, dropped: 0, rttMs: null, since: null,
    });
    expect(parseClient({ kind: 'http' })).toBeNull();
    expect(parseClient({ id: 2 })).toBeNull();
    expect(parseClient('http')).toBeNull();
    expect(parseClients({ clients: [] })).toBeNull();
    expect(parseClients(null)).toBeNull();
    expect(parseClients([STREAM, { bogus: true }, HTTP])?.map((c) => c.id)).toEqual([16, 17]);
  });

  it('lists streams first, then by id', () => {
    const other = { ...STREAM, id: 3, label: 'alice' };
    expect(parseClients([HTTP, STREAM, ANONYMOUS, other])!.map((c) => c.id)).toEqual([3, 16, 12, 17]);
  });
});

describe('how the numbers read', () => {
  it('bytes', () => {
    expect(bytesText(0)).toBe('0 B');
    expect(bytesText(999)).toBe('999 B');
    expect(bytesText(1536)).toBe('1.5 kB');
    expect(bytesText(12_345_678)).toBe('12.3 MB');
    expect(bytesText(1_200_000_000)).toBe('1.20 GB');
    expect(bytesText(NaN)).toBe('–');
  });

  it('topics: the first few and how many more; nothing for HTTP', () => {
    const stream = parseClient(STREAM)!;
    expect(topicsText(stream)).toBe('pose, scan, map +1');
    expect(topicsText(stream, 4)).toBe('pose, scan, map, status');
    expect(topicsText({ ...stream, topics: [] })).toBe('no topics');
    expect(topicsText(parseClient(HTTP)!)).toBe('');
  });

  it('the summary counts streams and the rest', () => {
    const list = parseClients([STREAM, HTTP, ANONYMOUS])!;
    expect(clientsSummary(list)).toBe('1 stream · 2 http');
    expect(clientsSummary([])).toBe('0 streams · 0 http');
  });
});

describe('what GET /clients says about the token', () => {
  it('403 is not an admin, 404 a server without the list, the rest unknown', () => {
    expect(clientsAccess(new ApiError(403, 'forbidden', 'this needs the admin role'))).toBe('not_admin');
    expect(clientsAccess(new ApiError(404, 'not_found', 'no such path'))).toBe('absent');
    expect(clientsAccess(new ApiError(0, 'network_error', 'server unreachable'))).toBe('unknown');
    expect(clientsAccess(new ApiError(500, 'internal', 'boom'))).toBe('unknown');
    expect(clientsAccess(new Error('?'))).toBe('unknown');
  });
});
