import { describe, expect, it } from 'vitest';
import { ApiError } from '../src/apierror';
import { parseZones, zoneErrorText, zoneRequest, zoneSummary } from '../src/zones';

describe('keep-out zones', () => {
  it('parse GET /zones, sorted by id, dropping malformed zones', () => {
    const zones = parseZones([
      { id: 4, name: 'dock', polygon: [[0, 0], [1, 0], [1, 1]] },
      { id: 2, polygon: [[0, 0], [2, 0], [2, 2], [0, 2]] },
      { id: 5, name: 'bad', polygon: [[0, 0], [1, 0]] },
      { name: 'no id', polygon: [[0, 0], [1, 0], [1, 1]] },
    ]);
    expect(zones.map((z) => [z.id, z.name, z.polygon.length])).toEqual([[2, '', 4], [4, 'dock', 3]]);
    expect(parseZones({ error: 1 })).toEqual([]);
  });

  it('build the POST body: millimetre vertices, a name only when given', () => {
    expect(zoneRequest([[1.23456, 2], [3, 4.0004], [5, 6]], '  ')).toEqual({ polygon: [[1.235, 2], [3, 4], [5, 6]] });
    expect(zoneRequest([[0, 0], [1, 0], [1, 1]], ' dock ')).toEqual({ name: 'dock', polygon: [[0, 0], [1, 0], [1, 1]] });
  });

  it('summarise a zone', () => {
    expect(zoneSummary({ id: 1, name: '', polygon: [[0, 0], [1.5, 0], [1.5, 1.5], [0, 1.5]] })).toBe('4 vertices · 2.25 m²');
  });

  it("show the server's own words for invalid_polygon", () => {
    expect(zoneErrorText(new ApiError(400, 'invalid_polygon', 'edges 0 and 2 cross'))).toBe('The server refused the polygon: edges 0 and 2 cross (invalid_polygon)');
    expect(zoneErrorText(new ApiError(404, 'not_found', 'x'))).toMatch(/no keep-out zones/);
  });
});
