import { describe, expect, it } from 'vitest';
import { ControllerChoice } from '../src/controllers';

describe('controller choice', () => {
  it('offers every contract controller until the server refuses one', () => {
    const c = new ControllerChoice();
    expect(c.options().map((o) => o.name)).toEqual(['lyapunov', 'dwa', 'vfh', 'pure_pursuit', 'potential_field']);
    expect(c.options().every((o) => o.available)).toBe(true);
    c.refuse('pure_pursuit');
    const pp = c.options().find((o) => o.name === 'pure_pursuit')!;
    expect(pp).toEqual({ name: 'pure_pursuit', label: 'Pure pursuit (not on this robot)', available: false });
    expect(c.pick('pure_pursuit')).toBe('lyapunov');
    expect(c.pick('vfh')).toBe('vfh');
    expect(c.pick('nonsense')).toBe('lyapunov');
  });

  it('never refuses the default, and forgets refusals for another server', () => {
    const c = new ControllerChoice();
    c.refuse('lyapunov');
    expect(c.isAvailable('lyapunov')).toBe(true);
    c.refuse('dwa');
    c.reset();
    expect(c.isAvailable('dwa')).toBe(true);
  });
});
