import { describe, expect, it } from 'vitest';
import { ApiError } from '../src/apierror';
import { loginErrorText, probeRole, roleTitle } from '../src/login';

/** A server whose answers per "METHOD path" are given; records what was asked. */
function server(answers: Record<string, number>) {
  const asked: string[] = [];
  const statusOf = async (method: string, path: string, body?: unknown) => {
    asked.push(`${method} ${path}${body === undefined ? '' : ` ${JSON.stringify(body)}`}`);
    return answers[`${method} ${path}`] ?? 0;
  };
  return { asked, statusOf };
}

describe('the role of a token', () => {
  it('is admin when the connection list answers', async () => {
    const s = server({ 'GET /api/v1/clients': 200 });
    expect(await probeRole(s.statusOf)).toBe('admin');
    expect(s.asked).toEqual(['GET /api/v1/clients']);
  });

  it('is operator when an empty lock action is refused for its body, viewer when for the role', async () => {
    const op = server({ 'GET /api/v1/clients': 403, 'POST /api/v1/operator': 400 });
    expect(await probeRole(op.statusOf)).toBe('operator');
    expect(op.asked[1]).toBe('POST /api/v1/operator {"action":""}');
    expect(await probeRole(server({ 'GET /api/v1/clients': 403, 'POST /api/v1/operator': 403 }).statusOf)).toBe('viewer');
  });

  it('asks the e-stop (without `engaged`) on a server without the lock', async () => {
    const s = server({ 'GET /api/v1/clients': 403, 'POST /api/v1/operator': 404, 'POST /api/v1/estop': 403 });
    expect(await probeRole(s.statusOf)).toBe('viewer');
    expect(s.asked[2]).toBe('POST /api/v1/estop {}');
  });

  it('is unknown when the server does not tell (unreachable, refused token)', async () => {
    expect(await probeRole(server({}).statusOf)).toBeNull();
    expect(await probeRole(server({ 'GET /api/v1/clients': 401 }).statusOf)).toBeNull();
    expect(await probeRole(server({ 'GET /api/v1/clients': 403, 'POST /api/v1/operator': 500 }).statusOf)).toBeNull();
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
