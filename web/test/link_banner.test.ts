import { describe, expect, it } from 'vitest';
import { bannerView } from '../src/link_banner';
import type { BannerInput } from '../src/link_banner';

const lost: BannerInput = { state: 'disconnected', everConnected: true, attempt: 3, nextInMs: 1840, reason: 'stalled: no data for 2 s', leaseMs: 300 };

describe('the disconnect banner', () => {
  it('says the robot stops by its lease, the attempt and when the next one goes', () => {
    expect(bannerView(lost)).toEqual({
      shown: true,
      title: 'Connection lost — the robot stops by itself within its teleop lease (300 ms); reconnecting…',
      detail: 'attempt 3 · next in 1.8 s · stalled: no data for 2 s',
    });
    expect(bannerView({ ...lost, state: 'connecting', nextInMs: null }).detail).toBe('attempt 3 · connecting now · stalled: no data for 2 s');
  });

  it('is gone while connected, signed out or refused, and before the first connection failed', () => {
    expect(bannerView({ ...lost, state: 'connected' }).shown).toBe(false);
    expect(bannerView({ ...lost, state: 'auth_error' }).shown).toBe(false);
    expect(bannerView({ ...lost, state: 'connecting', everConnected: false, attempt: 0 }).shown).toBe(false);
  });

  it('says the robot was never reached when the first connection fails', () => {
    const v = bannerView({ ...lost, everConnected: false, attempt: 1, reason: 'closed (1006)' });
    expect(v.title).toBe('Cannot reach the robot — reconnecting…');
    expect(v.detail).toBe('attempt 1 · next in 1.8 s · closed (1006)');
  });
});
