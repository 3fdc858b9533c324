// The operator lock as the Live page shows it: one person (one token) drives at a time. The body of
// GET/POST /api/v1/operator, who "this page" is (the server has no "who am I": the token id is
// learnt from an acquire's reply or from a command the server accepted), the line that says who
// drives, which buttons the Operator card offers in each state, and the words for refusals. Pure
// (no DOM, no fetch), unit-tested; operator_panel.ts renders it.

import { ApiError, errorText } from './apierror';

/** Who holds the lock (GET /api/v1/operator's `holder`). */
export interface OperatorHolder {
  tokenId: number;
  /** The token's label; null when the server sent none. */
  label: string | null;
  role: string | null;
  /** The peer as the server saw it, "ip:port". */
  address: string | null;
  /** Unix seconds. */
  since: number | null;
  /** The connection the holder last commanded on. */
  clientId: number | null;
}

export type OperatorAction = 'acquire' | 'release' | 'take_over';

/**
 * free: nobody drives; mine: this page's token drives; other: somebody else (known not to be this
 * token); held: somebody drives and this page cannot tell whether it is its own token (it has not
 * driven yet); unknown: not asked yet or not connected; unsupported: the server has no lock.
 */
export type LockState = 'unknown' | 'unsupported' | 'free' | 'mine' | 'other' | 'held';

/** What the page knows of its own token: its id once learnt, and token ids known to be others'. */
export interface Identity {
  me: number | null;
  notMe: ReadonlySet<number>;
}

export interface OperatorView {
  state: LockState;
  /** "driven by alice since 10:02 from 192.168.1.5", "nobody drives", ... */
  line: string;
  /** The full story for the line's tooltip (label, role, token id, address with port, date). */
  title: string;
  buttons: { acquire: boolean; release: boolean; takeOver: boolean };
  /** Said under the line when somebody else drives; null otherwise. */
  note: string | null;
  /** Teleop and goals are refused here without asking the server (somebody else surely drives). */
  blocksCommands: boolean;
  /** Why teleop and goals are refused, for their tooltips; null when they are not. */
  lockedReason: string | null;
}

const finite = (x: unknown): x is number => typeof x === 'number' && Number.isFinite(x);
const text = (x: unknown): string | null => (typeof x === 'string' && x.trim() !== '' ? x.trim() : null);

/** A holder object; null when it is not one (no usable token id). */
export function parseHolder(value: unknown): OperatorHolder | null {
  if (!value || typeof value !== 'object' || Array.isArray(value)) return null;
  const v = value as Record<string, unknown>;
  if (!finite(v.token_id) || !Number.isInteger(v.token_id) || v.token_id < 0) return null;
  return {
    tokenId: v.token_id,
    label: text(v.label),
    role: text(v.role),
    address: text(v.address),
    since: finite(v.since) && v.since > 0 ? v.since : null,
    clientId: finite(v.client_id) ? v.client_id : null,
  };
}

/**
 * The body of GET/POST /api/v1/operator: `{holder: null}` is a free lock; null when the body is
 * not one (no `holder` key, or a holder without a token id), so the caller keeps what it knew.
 */
export function parseOperatorBody(value: unknown): { holder: OperatorHolder | null } | null {
  if (!value || typeof value !== 'object' || Array.isArray(value)) return null;
  const v = value as Record<string, unknown>;
  if (!('holder' in v)) return null;
  if (v.holder === null) return { holder: null };
  const holder = parseHolder(v.holder);
  return holder ? { holder } : null;
}

/** The holder's name: the token's label, else its id. */
export function holderName(holder: OperatorHolder): string {
  return holder.label ?? `token #${holder.tokenId}`;
}

/** "ip:port" -> "ip" ("[v6]:port" -> "v6"); anything else as it is. */
export function hostOf(address: string): string {
  const bracketed = /^\[([^\]]+)\](?::\d+)?$/.exec(address);
  if (bracketed) return bracketed[1]!;
  const v4 = /^([^:]+):\d+$/.exec(address);
  return v4 ? v4[1]! : address;
}

/** Unix seconds -> "10:02" in local time. */
export function clockHm(unixSeconds: number): string {
  const d = new Date(unixSeconds * 1000);
  return `${String(d.getHours()).padStart(2, '0')}:${String(d.getMinutes()).padStart(2, '0')}`;
}

/** Where the lock stands for this page. */
export function lockState(holder: OperatorHolder | null | undefined, identity: Identity): LockState {
  if (holder === undefined) return 'unknown';
  if (holder === null) return 'free';
  if (identity.me !== null) return holder.tokenId === identity.me ? 'mine' : 'other';
  return identity.notMe.has(holder.tokenId) ? 'other' : 'held';
}

/** "driven by alice since 10:02 from 192.168.1.5", "you drive since ...", "nobody drives". */
export function holderLine(holder: OperatorHolder | null, mine: boolean, formatTime: (unix: number) => string = clockHm): string {
  if (!holder) return 'nobody drives';
  const since = holder.since !== null ? ` since ${formatTime(holder.since)}` : '';
  const from = holder.address ? ` from ${hostOf(holder.address)}` : '';
  return `${mine ? 'you drive' : `driven by ${holderName(holder)}`}${since}${from}`;
}

function holderTitle(holder: OperatorHolder | null): string {
  if (!holder) return 'Nobody holds the operator lock: the first teleop or goal takes it.';
  const parts = [
    `${holderName(holder)}${holder.role ? ` (${holder.role})` : ''}, token #${holder.tokenId}`,
    holder.address ? `at ${holder.address}` : null,
    holder.since !== null ? `since ${new Date(holder.since * 1000).toLocaleString()}` : null,
  ];
  return `${parts.filter((p) => p !== null).join(', ')}. The lock lapses when the holder's stream closes or 10 s after their last command.`;
}

/** Why a command from this page is refused while `holder` drives. */
export function refusalText(holder: OperatorHolder, admin: boolean | null): string {
  return `the robot is driven by ${holderName(holder)}: ask them to release it${admin ? ', or take over' : ''}`;
}

/** The Operator card, the teleop and goal controls in one state. */
export function operatorView(input: {
  supported: boolean | null;
  holder: OperatorHolder | null | undefined;
  identity: Identity;
  admin: boolean | null;
}): OperatorView {
  const none = { acquire: false, release: false, takeOver: false };
  if (input.supported === false) {
    return { state: 'unsupported', line: 'no operator lock on this server', title: 'GET /api/v1/operator answered 404', buttons: none, note: null, blocksCommands: false, lockedReason: null };
  }
  const state = lockState(input.holder, input.identity);
  const holder = input.holder ?? null;
  if (state === 'unknown' || !holder) {
    const unknown = state === 'unknown';
    return {
      state,
      line: unknown ? '–' : holderLine(null, false),
      title: unknown ? 'Not asked yet (GET /api/v1/operator, every 2 s while connected)' : holderTitle(null),
      buttons: unknown ? none : { ...none, acquire: true },
      note: null,
      blocksCommands: false,
      lockedReason: null,
    };
  }
  const admin = input.admin === true;
  if (state === 'mine') {
    return { state, line: holderLine(holder, true), title: holderTitle(holder), buttons: { ...none, release: true }, note: null, blocksCommands: false, lockedReason: null };
  }
  const reason = refusalText(holder, input.admin);
  return {
    state,
    line: holderLine(holder, false),
    title: holderTitle(holder),
    // Not knowing whether the holder is this very token (held), an acquire settles it: it keeps
    // the own lock, or is refused with operator_busy.
    buttons: { acquire: state === 'held', release: false, takeOver: admin },
    note: `Teleop and goals are refused while ${holderName(holder)} drives: ask them to release it${admin ? ', or take over' : ''}.`,
    // Only when surely somebody else's: a lock that may be the own one is left to the server.
    blocksCommands: state === 'other',
    lockedReason: `Refused: ${reason}.`,
  };
}

/** The confirmation asked before an admin takes the lock from `holder`. */
export function takeOverPrompt(holder: OperatorHolder): string {
  return `Take over from ${holderName(holder)}? They lose control of the robot at once.`;
}

/** Whether a request is a driving command the lock guards (a reply to it says who may drive). */
export function isDrivingCommand(method: string, path: string): boolean {
  if (method !== 'POST') return false;
  const bare = path.split('?')[0];
  return bare === '/api/v1/teleop' || bare === '/api/v1/goals' || bare === '/api/v1/follow';
}

/** Words for a refused POST /api/v1/operator. */
export function operatorErrorText(error: unknown, action: OperatorAction): string {
  if (!(error instanceof ApiError)) return errorText(error);
  switch (error.code) {
    case 'operator_busy':
      return `${error.message} (operator_busy)`;
    case 'not_holder':
      return `This page's token does not hold the lock any more: ${error.message} (not_holder)`;
    case 'forbidden':
      return action === 'take_over'
        ? 'Taking over needs the admin role (forbidden).'
        : 'This token may not drive: the operator role is needed (forbidden).';
    case 'not_found':
      return 'This server has no operator lock (404 not_found).';
    default:
      return error.describe();
  }
}
