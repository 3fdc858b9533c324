import { describe, expect, it } from 'vitest';
import { forgetToken, saveToken, splitUrlToken, storedToken } from '../src/auth';
import type { TokenStorages } from '../src/auth';

/** An in-memory Storage. */
class MemoryStorage implements Storage {
  private readonly items = new Map<string, string>();
  get length(): number {
    return this.items.size;
  }
  clear(): void {
    this.items.clear();
  }
  getItem(key: string): string | null {
    return this.items.get(key) ?? null;
  }
  key(index: number): string | null {
    return [...this.items.keys()][index] ?? null;
  }
  removeItem(key: string): void {
    this.items.delete(key);
  }
  setItem(key: string, value: string): void {
    this.items.set(key, value);
  }
}

const storages = (): TokenStorages & { session: MemoryStorage; local: MemoryStorage } => ({ session: new MemoryStorage(), local: new MemoryStorage() });

describe('where the token is kept', () => {
  it('keeps it for this tab by default, on this device when remembered, never in both', () => {
    const s = storages();
    expect(storedToken(s)).toBeNull();
    saveToken('abc', false, s);
    expect(s.session.length).toBe(1);
    expect(s.local.length).toBe(0);
    expect(storedToken(s)).toEqual({ token: 'abc', remembered: false });
    saveToken('abc', true, s);
    expect(s.session.length).toBe(0);
    expect(storedToken(s)).toEqual({ token: 'abc', remembered: true });
    // Not remembered any more: the device forgets it.
    saveToken('abc', false, s);
    expect(s.local.length).toBe(0);
  });

  it('prefers the tab token over the remembered one', () => {
    const s = storages();
    saveToken('device', true, s);
    s.session.setItem('mobot.token', 'tab');
    expect(storedToken(s)).toEqual({ token: 'tab', remembered: false });
  });

  it('forgets it everywhere on sign-out', () => {
    const s = storages();
    saveToken('a', true, s);
    s.session.setItem('mobot.token', 'b');
    forgetToken(s);
    expect(storedToken(s)).toBeNull();
  });

  it('works without storage (disabled by policy)', () => {
    const none: TokenStorages = { session: null, local: null };
    saveToken('x', true, none);
    expect(storedToken(none)).toBeNull();
    forgetToken(none);
  });
});

describe('?token= on the URL', () => {
  it('is taken off the address, other parameters and the hash kept', () => {
    expect(splitUrlToken('http://robot:8080/?token=s3cr%20t&x=1#runs')).toEqual({ token: 's3cr t', cleanUrl: '/?x=1#runs' });
    expect(splitUrlToken('http://robot:8080/dash/?token=t')).toEqual({ token: 't', cleanUrl: '/dash/' });
    expect(splitUrlToken('http://robot:8080/#live')).toBeNull();
    expect(splitUrlToken('http://robot:8080/?token=')).toBeNull();
  });
});
