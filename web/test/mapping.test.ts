import { describe, expect, it } from 'vitest';
import { ApiError } from '../src/apierror';
import { mappingErrorText, MappingState, parseMappingStatus, validateMapName } from '../src/mapping';

const idle = { mapping: false, scans: 0, nodes: 0, loop_closures: 0 };
const running = { mapping: true, scans: 120, nodes: 14, loop_closures: 2, started_t: 40 };

describe('map names', () => {
  it('refuses empty and blank names and names over 128 characters', () => {
    expect(validateMapName('')).toMatch(/Enter a name/);
    expect(validateMapName('   ')).toMatch(/Enter a name/);
    expect(validateMapName('x'.repeat(129))).toMatch(/129 characters/);
    expect(validateMapName(' lab 2 ')).toBeNull();
    expect(validateMapName('x'.repeat(128))).toBeNull();
  });
});

describe('GET /mapping bodies', () => {
  it('parses the status, started_t only while present', () => {
    expect(parseMappingStatus(running)).toEqual(running);
    expect(parseMappingStatus({ mapping: false })).toEqual(idle);
    expect(parseMappingStatus({ scans: 3 })).toBeNull();
    expect(parseMappingStatus(null)).toBeNull();
  });
});

describe('mapping panel state', () => {
  it('follows the server: idle offers Start only, mapping offers save and discard', () => {
    const s = new MappingState();
    expect(s.phase).toBe('unknown');
    s.onStatus(idle);
    expect(s.phase).toBe('idle');
    expect(s.controls()).toEqual({ start: true, save: false, discard: false, name: false, busy: false });
    s.onStatus(running);
    expect(s.phase).toBe('mapping');
    expect(s.controls()).toEqual({ start: false, save: true, discard: true, name: true, busy: false });
    expect(s.summary()).toBe('scans 120 · nodes 14 · loop closures 2');
    expect(s.elapsed(52.5)).toBe(12.5);
  });

  it('start: starting while the request runs (polls do not interfere), mapping once accepted', () => {
    const s = new MappingState();
    s.onStatus(idle);
    expect(s.refusal('start')).toBeNull();
    s.begin('start');
    expect(s.phase).toBe('starting');
    expect(s.controls().busy).toBe(true);
    expect(s.controls().start).toBe(false);
    s.onStatus(idle); // a poll answered before the start took effect
    expect(s.phase).toBe('starting');
    s.succeeded('start', { mapping: true });
    expect(s.phase).toBe('mapping');
    expect(s.status?.mapping).toBe(true);
  });

  it('Stop & save needs a name: an empty one is refused without a request', () => {
    const s = new MappingState();
    s.onStatus(running);
    expect(s.refusal('save', '')).toMatch(/Enter a name/);
    expect(s.refusal('save', 'office 2')).toBeNull();
    expect(s.refusal('discard')).toBeNull();
  });

  it('a save stores the new map id and name and goes idle', () => {
    const s = new MappingState();
    s.onStatus(running);
    s.begin('save');
    expect(s.phase).toBe('saving');
    expect(s.mapping).toBe(true);
    s.succeeded('save', { mapping: false, map_id: 7 }, ' lab ');
    expect(s.phase).toBe('idle');
    expect(s.saved).toEqual({ id: 7, name: 'lab' });
    expect(s.controls().start).toBe(true);
  });

  it('a discard goes idle without a saved map', () => {
    const s = new MappingState();
    s.onStatus(running);
    s.begin('discard');
    s.succeeded('discard', { mapping: false });
    expect([s.phase, s.saved]).toEqual(['idle', null]);
  });

  it('refusals say what the server knows: mapping_active means mapping, not_mapping means idle', () => {
    const s = new MappingState();
    s.onStatus(idle);
    s.begin('start');
    s.failed('start', new ApiError(409, 'mapping_active', 'mapping is already running'));
    expect(s.phase).toBe('mapping');
    expect(s.error).toMatch(/already running/);
    s.begin('save');
    s.failed('save', new ApiError(409, 'not_mapping', 'not mapping'));
    expect(s.phase).toBe('idle');
    s.begin('start');
    s.failed('start', new ApiError(403, 'forbidden', 'operator role needed'));
    expect([s.phase, s.error]).toEqual(['idle', 'This token may not map (the operator role is needed).']);
    s.onStatus(running);
    s.begin('save');
    s.failed('save', new ApiError(500, 'internal_error', 'disk full'));
    expect(s.phase).toBe('mapping');
    expect(s.error).toBe('disk full (internal_error)');
  });

  it('a server without /mapping (404 not_found) disables everything', () => {
    const s = new MappingState();
    s.onUnsupported();
    expect(s.phase).toBe('unsupported');
    expect(s.controls()).toEqual({ start: false, save: false, discard: false, name: false, busy: false });
    expect(s.refusal('start')).toMatch(/cannot build maps/);
    expect(s.modeDisagrees('mapping')).toBe(false);
    const t = new MappingState();
    t.begin('start');
    t.failed('start', new ApiError(404, 'not_found', 'no such path'));
    expect(t.phase).toBe('unsupported');
    expect(mappingErrorText(new ApiError(404, 'not_found', 'x'))).toMatch(/no \/api\/v1\/mapping/);
  });

  it('asks for GET /mapping when the robot mode disagrees with the panel', () => {
    const s = new MappingState();
    s.onStatus(idle);
    expect(s.modeDisagrees('mapping')).toBe(true);
    expect(s.modeDisagrees('idle')).toBe(false);
    s.onStatus(running);
    expect(s.modeDisagrees('teleop')).toBe(true);
    expect(s.modeDisagrees('mapping')).toBe(false);
    s.begin('save');
    expect(s.modeDisagrees('idle')).toBe(false); // our own request is under way
  });

  it('bumps its version on every change', () => {
    const s = new MappingState();
    const v = s.version;
    s.onStatus(idle);
    s.showError('x');
    expect(s.version).toBe(v + 2);
  });
});
