// A plan's warnings for people (issue 29, defect 6): numbers rounded as a person writes them
// ("119.99000000000001 m" → "120 m"), repeats grouped with their count, in first-seen order.

/** A number's text as a person writes it: five significant digits, no floating-point noise. */
export function humanNumber(text: string): string {
  const x = Number(text);
  if (!Number.isFinite(x)) return text;
  const r = Number(x.toPrecision(5));
  return String(Object.is(r, -0) ? 0 : r);
}

/** The message with every decimal number of more than two decimals rounded (integers are left as they are). */
export function humanText(message: string): string {
  return message.replace(/-?\d+\.\d{3,}(?:e[-+]?\d+)?/gi, (m) => humanNumber(m));
}

export interface WarningGroup {
  text: string;
  count: number;
  /** the messages as the server wrote them (distinct), for a tooltip */
  raw: string[];
}

export function groupWarnings(warnings: readonly string[]): WarningGroup[] {
  const groups = new Map<string, WarningGroup>();
  for (const w of warnings) {
    const text = humanText(String(w));
    const g = groups.get(text);
    if (g) {
      g.count++;
      if (!g.raw.includes(w)) g.raw.push(w);
    } else groups.set(text, { text, count: 1, raw: [w] });
  }
  return [...groups.values()];
}
