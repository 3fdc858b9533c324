import { describe, expect, it } from 'vitest';
import { PolygonDraft } from '../src/polygon_tool';

const TOL = 0.1;

function drawn(points: [number, number][]): PolygonDraft {
  const d = new PolygonDraft();
  d.start();
  for (const p of points) d.click(p, TOL);
  return d;
}

describe('polygon drawing', () => {
  it('adds a vertex per click and follows the pointer', () => {
    const d = new PolygonDraft();
    expect(d.click([0, 0], TOL)).toEqual({ kind: 'none' }); // not drawing yet
    d.start();
    expect(d.active).toBe(true);
    expect(d.click([0, 0], TOL)).toEqual({ kind: 'added', vertices: 1 });
    expect(d.click([1, 0], TOL)).toEqual({ kind: 'added', vertices: 2 });
    d.move([1, 1]);
    expect(d.cursor).toEqual([1, 1]);
    expect(d.vertices).toEqual([[0, 0], [1, 0]]);
  });

  it('closes on Enter (close) with 3 or more vertices and waits for the server', () => {
    const d = drawn([[0, 0], [1, 0], [1, 1]]);
    expect(d.close()).toEqual({ kind: 'closed', polygon: [[0, 0], [1, 0], [1, 1]] });
    expect(d.state).toBe('submitting');
    expect(d.click([5, 5], TOL)).toEqual({ kind: 'none' });
    d.accepted();
    expect(d.state).toBe('idle');
    expect(d.vertices).toEqual([]);
  });

  it('refuses to close with fewer than 3 vertices and keeps drawing', () => {
    const d = drawn([[0, 0], [1, 0]]);
    const result = d.close();
    expect(result.kind).toBe('refused');
    expect(result.kind === 'refused' && result.reason).toMatch(/at least 3 vertices: click 1 more/);
    expect(d.active).toBe(true);
  });

  it('treats a double click as one vertex and a close: the second click is ignored', () => {
    // The browser sends click, click, dblclick: the tool sees two clicks at the same point, then close.
    const d = drawn([[0, 0], [1, 0]]);
    expect(d.click([1, 1], TOL)).toEqual({ kind: 'added', vertices: 3 });
    expect(d.click([1.02, 1], TOL)).toEqual({ kind: 'ignored' });
    expect(d.close()).toEqual({ kind: 'closed', polygon: [[0, 0], [1, 0], [1, 1]] });
  });

  it('closes on a click at the first vertex', () => {
    const d = drawn([[0, 0], [1, 0], [1, 1]]);
    expect(d.click([0.05, -0.05], TOL)).toEqual({ kind: 'closed', polygon: [[0, 0], [1, 0], [1, 1]] });
  });

  it('cancels on Esc, from drawing or while the server has it', () => {
    const d = drawn([[0, 0], [1, 0]]);
    expect(d.cancel()).toEqual({ kind: 'canceled' });
    expect([d.state, d.vertices.length]).toEqual(['idle', 0]);
    expect(d.cancel()).toEqual({ kind: 'none' });
  });

  it('reopens a refused polygon with its vertices; Backspace takes one back', () => {
    const d = drawn([[0, 0], [2, 2], [2, 0], [0, 2]]);
    expect(d.problem).toBe('edges cross');
    expect(d.close().kind).toBe('closed'); // sent anyway: the server's message says why it is refused
    d.reopen();
    expect(d.active).toBe(true);
    expect(d.undo()).toEqual({ kind: 'added', vertices: 3 });
    expect(d.problem).toBeNull();
  });

  it('stops adding at 256 vertices', () => {
    const d = new PolygonDraft();
    d.start();
    for (let i = 0; i < 256; i++) d.click([i, (i * i) % 7], 0.01);
    expect(d.vertices.length).toBe(256);
    const result = d.click([1000, 1000], 0.01);
    expect(result.kind === 'refused' && result.reason).toMatch(/at most 256/);
  });

  it('a new start drops the previous draft', () => {
    const d = drawn([[0, 0], [1, 0]]);
    d.start();
    expect(d.vertices).toEqual([]);
  });
});
