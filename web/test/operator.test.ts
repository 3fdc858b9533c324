import { describe, expect, it } from 'vitest';
import { ApiError } from '../src/apierror';
import {
  clockHm,
  holderLine,
  holderName,
  hostOf,
  isDrivingCommand,
  lockState,
  operatorErrorText,
  operatorView,
  parseHolder,
  parseOperatorBody,
  refusalText,
  takeOverPrompt,
} from '../src/operator';
import type { Identity, OperatorHolder } from '../src/operator';

/** 10:02 local time on some day, in Unix seconds (the line is in local time). */
const AT_10_02 = new Date(2026, 11, 5, 10, 2, 30).getTime() / 1000;

const ALICE_BODY = { client_id: 7, token_id: 3, label: 'alice', role: 'operator', address: '192.168.1.5:51234', since: AT_10_02 };
const ALICE: OperatorHolder = { clientId: 7, tokenId: 3, label: 'alice', role: 'operator', address: '192.168.1.5:51234', since: AT_10_02 };
const ADMIN: OperatorHolder = { clientId: 2, tokenId: 0, label: 'admin (--token)', role: 'admin', address: '127.0.0.1:40000', since: AT_10_02 };

const nobody: Identity = { me: null, notMe: new Set() };
const asAdminToken: Identity = { me: 0, notMe: new Set() };

describe('GET/POST /operator bodies', () => {
  it('parses a holder and a free lock', () => {
    expect(parseOperatorBody({ holder: ALICE_BODY })).toEqual({ holder: ALICE });
    expect(parseOperatorBody({ holder: null })).toEqual({ holder: null });
  });

  it('keeps a holder whose optional fields are missing or odd, without inventing them', () => {
    expect(parseHolder({ token_id: 0 })).toEqual({ tokenId: 0, label: null, role: null, address: null, since: null, clientId: null });
    expect(parseHolder({ token_id: 4, label: '  ', role: 7, address: '', since: 'yesterday', client_id: NaN })).toEqual({
      tokenId: 4, label: null, role: null, address: null, since: null, clientId: null,
    });
  });

  it('refuses bodies that are not one, so the page keeps what it knew', () => {
    expect(parseOperatorBody(null)).toBeNull();
    expect(parseOperatorBody([])).toBeNull();
    expect(parseOperatorBody({})).toBeNull();
    expect(parseOperatorBody({ error: { code: 'operator_busy' } })).toBeNull();
    expect(parseOperatorBody({ holder: { label: 'bob' } })).toBeNull();
    expect(parseOperatorBody({ holder: { token_id: -1 } })).toBeNull();
    expect(parseOperatorBody({ holder: { token_id: 1.5 } })).toBeNull();
    expect(parseOperatorBody({ holder: 'bob' })).toBeNull();
  });
});

describe('the holder line', () => {
  it('says who drives, since when and from where (host without the port)', () => {
    expect(holderLine(ALICE, false)).toBe('driven by alice since 10:02 from 192.168.1.5');
    expect(holderLine(ALICE, true)).toBe('you drive since 10:02 from 192.168.1.5');
    expect(holderLine(null, false)).toBe('nobody drives');
  });

  it('leaves out what it does not know, and names an unlabelled token by its id', () => {
    const bare = { ...ALICE, label: null, since: null, address: null };
    expect(holderName(bare)).toBe('token #3');
    expect(holderLine(bare, false)).toBe('driven by token #3');
    expect(holderLine(ALICE, false, () => 'then')).toBe('driven by alice since then from 192.168.1.5');
  });

  it('formats hours and minutes with two digits, and hosts of every shape', () => {
    expect(clockHm(new Date(2026, 0, 1, 9, 5).getTime() / 1000)).toBe('09:05');
    expect(hostOf('10.0.0.2:8080')).toBe('10.0.0.2');
    expect(hostOf('[::1]:8080')).toBe('::1');
    expect(hostOf('[fe80::1]')).toBe('fe80::1');
    expect(hostOf('fe80::1')).toBe('fe80::1');
    expect(hostOf('robot.local')).toBe('robot.local');
  });
});

describe('who this page is', () => {
  it('mine or other once its token id is known; held while it cannot tell', () => {
    expect(lockState(undefined, asAdminToken)).toBe('unknown');
    expect(lockState(null, nobody)).toBe('free');
    expect(lockState(ADMIN, asAdminToken)).toBe('mine');
    expect(lockState(ALICE, asAdminToken)).toBe('other');
    expect(lockState(ALICE, nobody)).toBe('held');
    // A token the server refused us for is somebody else's.
    expect(lockState(ALICE, { me: null, notMe: new Set([3]) })).toBe('other');
    // Knowing the own id wins over an old guess.
    expect(lockState(ALICE, { me: 3, notMe: new Set([3]) })).toBe('mine');
  });
});

describe('the Operator card in each state', () => {
  const view = (holder: OperatorHolder | null | undefined, identity: Identity, admin: boolean | null = false, supported: boolean | null = true) =>
    operatorView({ supported, holder, identity, admin });

  it('free: Take control; nothing is refused', () => {
    const v = view(null, asAdminToken);
    expect(v.state).toBe('free');
    expect(v.line).toBe('nobody drives');
    expect(v.buttons).toEqual({ acquire: true, release: false, takeOver: false });
    expect(v.note).toBeNull();
    expect(v.blocksCommands).toBe(false);
    expect(v.lockedReason).toBeNull();
  });

  it('mine: Release only', () => {
    const v = view(ADMIN, asAdminToken, true);
    expect(v.state).toBe('mine');
    expect(v.line).toBe('you drive since 10:02 from 127.0.0.1');
    expect(v.buttons).toEqual({ acquire: false, release: true, takeOver: false });
    expect(v.blocksCommands).toBe(false);
  });

  it('other, as an operator: no button, teleop and goals refused, "ask them to release it"', () => {
    const v = view(ALICE, asAdminToken, false);
    expect(v.state).toBe('other');
    expect(v.line).toBe('driven by alice since 10:02 from 192.168.1.5');
    expect(v.buttons).toEqual({ acquire: false, release: false, takeOver: false });
    expect(v.blocksCommands).toBe(true);
    expect(v.note).toContain('ask them to release it');
    expect(v.note).not.toContain('take over');
    expect(v.lockedReason).toBe('Refused: the robot is driven by alice: ask them to release it.');
  });

  it('other, as an admin: Take over too', () => {
    const v = view(ALICE, asAdminToken, true);
    expect(v.buttons).toEqual({ acquire: false, release: false, takeOver: true });
    expect(v.note).toContain('or take over');
    expect(v.lockedReason).toContain('or take over');
  });

  it('held (perhaps this very token): Take control settles it, nothing is refused here', () => {
    const v = view(ALICE, nobody, true);
    expect(v.state).toBe('held');
    expect(v.line).toBe('driven by alice since 10:02 from 192.168.1.5');
    expect(v.buttons).toEqual({ acquire: true, release: false, takeOver: true });
    expect(v.blocksCommands).toBe(false);
  });

  it('unknown (not asked, disconnected) and unsupported (404): no buttons, nothing refused', () => {
    const unknown = view(undefined, asAdminToken, true);
    expect(unknown.state).toBe('unknown');
    expect(unknown.line).toBe('–');
    expect(unknown.buttons).toEqual({ acquire: false, release: false, takeOver: false });
    const unsupported = view(ALICE, asAdminToken, true, false);
    expect(unsupported.state).toBe('unsupported');
    expect(unsupported.blocksCommands).toBe(false);
    expect(unsupported.buttons).toEqual({ acquire: false, release: false, takeOver: false });
  });
});

describe('words', () => {
  it('the take-over confirmation and the local refusal name the holder', () => {
    expect(takeOverPrompt(ALICE)).toBe('Take over from alice? They lose control of the robot at once.');
    expect(refusalText(ALICE, false)).toBe('the robot is driven by alice: ask them to release it');
    expect(refusalText(ALICE, true)).toBe('the robot is driven by alice: ask them to release it, or take over');
  });

  it('explains each refusal of POST /operator', () => {
    const busy = new ApiError(409, 'operator_busy', 'the robot is driven by bob (token 2); ask them to release it, or an admin may take over');
    expect(operatorErrorText(busy, 'acquire')).toBe(`${busy.message} (operator_busy)`);
    expect(operatorErrorText(new ApiError(409, 'not_holder', 'held by somebody else'), 'release')).toContain('(not_holder)');
    expect(operatorErrorText(new ApiError(403, 'forbidden', 'take_over needs the admin role'), 'take_over')).toBe('Taking over needs the admin role (forbidden).');
    expect(operatorErrorText(new ApiError(403, 'forbidden', 'this needs the operator role'), 'acquire')).toContain('operator role');
    expect(operatorErrorText(new ApiError(404, 'not_found', 'no such path'), 'acquire')).toContain('no operator lock');
    expect(operatorErrorText(new ApiError(500, 'internal', 'boom'), 'acquire')).toBe('boom (internal)');
    expect(operatorErrorText(new Error('offline'), 'acquire')).toBe('offline');
  });

  it('knows which requests are driving commands', () => {
    expect(isDrivingCommand('POST', '/api/v1/teleop')).toBe(true);
    expect(isDrivingCommand('POST', '/api/v1/goals')).toBe(true);
    expect(isDrivingCommand('POST', '/api/v1/follow')).toBe(true);
    // Stopping is never locked, and reading is not driving.
    expect(isDrivingCommand('DELETE', '/api/v1/follow')).toBe(false);
    expect(isDrivingCommand('DELETE', '/api/v1/goals/3')).toBe(false);
    expect(isDrivingCommand('GET', '/api/v1/goals')).toBe(false);
    expect(isDrivingCommand('POST', '/api/v1/estop')).toBe(false);
    expect(isDrivingCommand('POST', '/api/v1/operator')).toBe(false);
  });
});
