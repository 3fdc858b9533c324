// The bearer token: from ?token= on the page URL (what mobotd prints), else from localStorage.

const STORAGE_KEY = 'mobot.token';

function storage(): Storage | null {
  try {
    return window.localStorage;
  } catch {
    return null; // storage disabled
  }
}

/** Reads the token; a ?token= on the URL wins, is stored and removed from the address bar. */
export function initialToken(): string {
  const url = new URL(window.location.href);
  const fromUrl = url.searchParams.get('token');
  if (fromUrl) {
    saveToken(fromUrl);
    url.searchParams.delete('token');
    window.history.replaceState(null, '', url.pathname + url.search + url.hash);
    return fromUrl;
  }
  return storage()?.getItem(STORAGE_KEY) ?? '';
}

export function saveToken(token: string): void {
  storage()?.setItem(STORAGE_KEY, token);
}

export function forgetToken(): void {
  storage()?.removeItem(STORAGE_KEY);
}

/** Base path of the app ('' when served at '/'), so REST and the stream work behind a prefix. */
export function basePath(): string {
  return new URL('./', window.location.href).pathname.replace(/\/$/, '');
}

export function streamUrl(token: string): string {
  const scheme = window.location.protocol === 'https:' ? 'wss' : 'ws';
  return `${scheme}://${window.location.host}${basePath()}/api/v1/stream?token=${encodeURIComponent(token)}`;
}
