// Signing in: what a token may do (its role) and the words of the login view. The server has no
// "who am I", so the role is read from refusals that change nothing: GET /api/v1/clients answers
// an admin only, and a POST /api/v1/operator with an empty action is refused for its body (400)
// when the role may drive, for the role (403) when it may not, because the server checks the role
// before the body (docs/api.md "Authentication and roles"). A refused request is not audited.
// Pure (the requests are injected), unit-tested; main.ts renders it.

import { ApiError, errorText } from './apierror';

export type Role = 'viewer' | 'operator' | 'admin';

/** Answers a request with its HTTP status, 0 when the server is unreachable (never throws). */
export type StatusOf = (method: string, path: string, body?: unknown) => Promise<number>;

const isOk = (status: number) => status >= 200 && status < 300;

/** The token's role, null when the answers do not tell (unreachable, refused token, odd server). */
export async function probeRole(statusOf: StatusOf): Promise<Role | null> {
  const clients = await statusOf('GET', '/api/v1/clients');
  if (isOk(clients)) return 'admin';
  if (clients !== 403) return null;
  let drive = await statusOf('POST', '/api/v1/operator', { action: '' });
  // A server without the operator lock: an e-stop without `engaged` is refused the same way.
  if (drive === 404) drive = await statusOf('POST', '/api/v1/estop', {});
  if (drive === 400 || drive === 409) return 'operator';
  if (drive === 403) return 'viewer';
  return null;
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
