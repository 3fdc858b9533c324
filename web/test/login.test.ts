import { describe, expect, it } from 'vitest';
import { ApiError } from '../src/apierror';
import { loginErrorText, parseWhoami, roleTitle, signedInText } from '../src/login';

describe('who the token is', () => {
  it('reads the whoami body', () => {
    const alice = parseWhoami({ token_id: 7, label: 'alice', role: 'operator', expires_at: 1796000000 });
    expect(alice).toEqual({ tokenId: 7, label: 'alice', role: 'operator', expiresAt: 1796000000 });
    expect(signedInText(alice!)).toBe('alice (operator)');
    const admin = parseWhoami({ token_id: 0, label: '', role: 'admin', expires_at: null });
    expect(admin?.expiresAt).toBeNull();
    expect(signedInText(admin!)).toBe('admin');
  });

  it('is nobody when the body is not a whoami', () => {
    expect(parseWhoami(null)).toBeNull();
    expect(parseWhoami({ token_id: -1, label: 'x', role: 'viewer' })).toBeNull();
    expect(parseWhoami({ token_id: 1.5, label: 'x', role: 'viewer' })).toBeNull();
    expect(parseWhoami({ token_id: 1, label: 'x', role: 'root' })).toBeNull();
    expect(parseWhoami({ id: 1, role: 'viewer' })).toBeNull();
    expect(roleTitle(null)).toMatch(/could not be read/);
  });
});

describe('the login view says why', () => {
  it('tells a refused token from a server that does not answer', () => {
    expect(loginErrorText(new ApiError(401, 'unauthorized', 'unknown token'))).toBe('The server refused this token (unknown token). Check it and try again.');
    expect(loginErrorText(new ApiError(0, 'network_error', 'server unreachable (Failed to fetch)'))).toMatch(/^mobotd did not answer/);
    expect(loginErrorText(new ApiError(500, 'internal', 'boom'))).toBe('Sign-in failed: boom (internal)');
  });
});
