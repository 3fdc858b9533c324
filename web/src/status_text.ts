// Status values that wrap where they may and nowhere else, so a narrow side panel shows them
// whole: a value of several parts ("v -0.35 m/s", "w -1.00 rad/s") breaks between its parts, the
// localization method's detail after a '+' or ','.

import { detailPieces, methodLabel, parseMethod } from './localization';
import { h } from './ui';

/**
 * Writes a value as parts that wrap between them but never inside one ("v -0.35 m/s" / "w -1.00
 * rad/s"); the text reads as before (parts joined by a space).
 */
export function setParts(el: HTMLElement, parts: string[]): void {
  const text = parts.join(' ');
  if (el.dataset.text === text) return;
  el.dataset.text = text;
  // Spaces between the parts: where a line may break, and what textContent reads.
  el.replaceChildren(...parts.flatMap((part, i) => [...(i > 0 ? [' '] : []), h('span', { class: 'part', text: part })]));
  el.title = text;
}

/** The localization method: its family, then the detail (fused sets, particle count) muted and wrapping. */
export function showMethod(el: HTMLElement, raw: string | undefined): void {
  const method = parseMethod(raw);
  const key = method?.raw ?? '–';
  if (el.dataset.text === key) return;
  el.dataset.text = key;
  el.title = key;
  if (!method) {
    el.textContent = '–';
    return;
  }
  el.replaceChildren(
    h('span', { class: 'part', text: methodLabel(method) }),
    ...(method.detail ? [' ', methodDetail(method.detail)] : []),
  );
}

/** The detail with break opportunities after each '+' and ',' (not inside a sensor's name). */
export function methodDetail(detail: string): HTMLElement {
  const pieces = detailPieces(detail);
  return h('span', { class: 'detail' }, ...pieces.flatMap((piece, i) => (i < pieces.length - 1 ? [piece, h('wbr')] : [piece])));
}
