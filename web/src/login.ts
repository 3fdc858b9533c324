// Signing in: who the token is (GET /api/v1/whoami: its id, label, role and expiry) and the words
// of the login view. Pure, unit-tested; main.ts renders it.

import { ApiError, errorText } from './apierror';

export type Role = 'viewer' | 'operator' | 'admin';

/** The signed-in token as the server names it in the operator lock and the client list. */
export interface SignedInAs {
  tokenId: number;
  label: string;
  role: Role;
  /** Unix seconds from which the token is refused; null: until it is revoked. */
  expiresAt: number | null;
}

const ROLES: readonly string[] = ['viewer', 'operator', 'admin'];

/** A GET /api/v1/whoami body; null when it is not one. */
export function parseWhoami(value: unknown): SignedInAs | null {
  if (typeof value !== 'object' || value === null) return null;
  const v = value as Record<string, unknown>;
  if (typeof v.token_id !== 'number' || !Number.isInteger(v.token_id) || v.token_id < 0) return null;
  if (typeof v.role !== 'string' || !ROLES.includes(v.role)) return null;
  const expiresAt = typeof v.expires_at === 'number' && Number.isFinite(v.expires_at) ? v.expires_at : null;
  return { tokenId: v.token_id, label: typeof v.label === 'string' ? v.label : '', role: v.role as Role, expiresAt };
}

/** "alice (operator)", or the role alone for a token without a label. */
export function signedInText(who: SignedInAs): string {
  return who.label ? `${who.label} (${who.role})` : who.role;
}

/** What the role may do, for the tooltip of the role shown after login. */
export function roleTitle(role: Role | null): string {
  switch (role) {
    case 'admin':
      return 'admin: may drive, take the operator lock over, manage maps and tokens';
    case 'operator':
      return 'operator: may drive, send goals and engage the e-stop';
    case 'viewer':
      return 'viewer: may watch; driving, goals and the e-stop are refused';
    default:
      return 'the role of this token could not be read';
  }
}

/** Why the login view is shown again after the server turned a token down. */
export function loginErrorText(error: unknown): string {
  if (error instanceof ApiError) {
    if (error.status === 401) return `The server refused this token (${error.message}). Check it and try again.`;
    if (error.status === 0) return `mobotd did not answer (${error.message}). Is it running, and is this its address?`;
    return `Sign-in failed: ${error.describe()}`;
  }
  return `Sign-in failed: ${errorText(error)}`;
}

/** The words of the login view after the stream was closed with 4401. */
export const REVOKED_TEXT = 'Your token was revoked or has expired. Sign in with a valid token.';
