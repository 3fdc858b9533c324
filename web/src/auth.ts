// The bearer token: typed into the login view and kept for this tab (sessionStorage) or, when
// "remember me" is ticked, on this device (localStorage). A ?token= on the page URL (what mobotd
// prints, what scripts and tests open) is taken once, kept for this tab only, and removed from the
// address bar so it stays out of the history and of bookmarks. Also the URLs REST and the stream
// use: relative to the page, so the dashboard works behind a prefix or a proxy.

const STORAGE_KEY = 'mobot.token';

/** Where the token may be kept; null when the browser refuses storage. */
export interface TokenStorages {
  session: Storage | null;
  local: Storage | null;
}

function browserStorages(): TokenStorages {
  // Each may throw (storage disabled by policy, an opaque origin): then it is simply not used.
  const get = (name: 'sessionStorage' | 'localStorage'): Storage | null => {
    try {
      return window[name];
    } catch {
      return null;
    }
  };
  return { session: get('sessionStorage'), local: get('localStorage') };
}

function read(storage: Storage | null): string {
  try {
    return storage?.getItem(STORAGE_KEY) ?? '';
  } catch {
    return '';
  }
}

function write(storage: Storage | null, token: string): void {
  try {
    storage?.setItem(STORAGE_KEY, token);
  } catch {
    // quota or policy: the token then lives only in the page
  }
}

function remove(storage: Storage | null): void {
  try {
    storage?.removeItem(STORAGE_KEY);
  } catch {
    // nothing stored
  }
}

/** A token and whether it is remembered on this device. */
export interface StoredToken {
  token: string;
  remembered: boolean;
}

/** The token kept for this tab, else the one remembered on this device; null when none. */
export function storedToken(storages: TokenStorages = browserStorages()): StoredToken | null {
  const session = read(storages.session);
  if (session) return { token: session, remembered: false };
  const local = read(storages.local);
  return local ? { token: local, remembered: true } : null;
}

/**
 * Keeps a token that the server accepted: on this device when `remember`, else for this tab only.
 * The other place is cleared, so a token not remembered any more does not come back next time.
 */
export function saveToken(token: string, remember: boolean, storages: TokenStorages = browserStorages()): void {
  if (remember) {
    write(storages.local, token);
    remove(storages.session);
  } else {
    write(storages.session, token);
    remove(storages.local);
  }
}

/** Sign out (or a revoked token): forgotten in both places. */
export function forgetToken(storages: TokenStorages = browserStorages()): void {
  remove(storages.session);
  remove(storages.local);
}

/**
 * The ?token= of `href`, and the address without it (path, other parameters and hash kept); null
 * when there is none.
 */
export function splitUrlToken(href: string): { token: string; cleanUrl: string } | null {
  const url = new URL(href);
  const token = url.searchParams.get('token');
  if (!token) return null;
  url.searchParams.delete('token');
  return { token, cleanUrl: url.pathname + url.search + url.hash };
}

/** Takes a ?token= off the address bar (replaceState: no history entry keeps it); null when none. */
export function takeUrlToken(): string | null {
  const split = splitUrlToken(window.location.href);
  if (!split) return null;
  window.history.replaceState(null, '', split.cleanUrl);
  return split.token;
}

/** Base path of the app ('' when served at '/'), so REST and the stream work behind a prefix. */
export function basePath(): string {
  return new URL('./', window.location.href).pathname.replace(/\/$/, '');
}

/** The stream's URL on the host the page came from (through whatever proxy served it). */
export function streamUrl(token: string): string {
  const scheme = window.location.protocol === 'https:' ? 'wss' : 'ws';
  return `${scheme}://${window.location.host}${basePath()}/api/v1/stream?token=${encodeURIComponent(token)}`;
}
