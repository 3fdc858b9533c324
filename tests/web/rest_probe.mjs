// A REST request whose refusal is part of what a step checks: the status, the error code and the
// body, never a throw (dashboard.test.mjs's rest() is this, throwing on anything but 2xx).
export async function restProbe(base, token, method, path, body) {
  const response = await fetch(base + path, {
    method,
    headers: { Authorization: `Bearer ${token}`, ...(body ? { 'Content-Type': 'application/json' } : {}) },
    body: body ? JSON.stringify(body) : undefined,
  });
  const text = await response.text();
  let json = null;
  try {
    json = JSON.parse(text);
  } catch {
    // not JSON
  }
  return { status: response.status, code: json?.error?.code ?? null, json, text };
}
