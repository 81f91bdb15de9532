// A mission's plans as GET /missions/{id}/plans lists them (newest first): their labels in the Plan
// tab's list and the plan shown when the mission is opened.
import type { JobState } from './events.ts';

/** A plan job in the mission's listing (GET /missions/{id}/plans, newest first). */
export interface PlanSummary {
  id: number;
  revision: number;
  state: JobState;
  planner: string | null;
  params: Record<string, unknown>;
  created: string | null;
  finished: string | null;
  metrics: Record<string, number>;
}

/** "#12 · darp · PoC 98.1 % · rev 2 · 14:05" (the state instead of PoC when not done; the date when not today;
 *  "wall 97.3 %" for a structure scan). */
export function planLabel(p: PlanSummary, now = new Date()): string {
  const when = p.finished ?? p.created;
  let time = '';
  if (when) {
    const d = new Date(when);
    const hm = d.toLocaleTimeString(undefined, { hour: '2-digit', minute: '2-digit' });
    time = d.toDateString() === now.toDateString() ? hm : `${d.toLocaleDateString(undefined, { month: 'short', day: 'numeric' })} ${hm}`;
  }
  // a structure scan's figure is the wall's coverage: its ground PoC says nothing of the facade
  const poc =
    typeof p.metrics?.facade_poc === 'number'
      ? `wall ${(p.metrics.facade_poc * 100).toFixed(1)} %`
      : typeof p.metrics?.poc === 'number'
        ? `PoC ${(p.metrics.poc * 100).toFixed(1)} %`
        : '';
  const parts = [`#${p.id}`, p.planner ?? '', p.state === 'done' ? poc : p.state, `rev ${p.revision}`, time];
  return parts.filter((x) => x).join(' · ');
}

/** The plan shown when a mission is opened: the newest that is done (failed and cancelled ones have no files). */
export function latestDone(items: PlanSummary[]): PlanSummary | undefined {
  return items.find((p) => p.state === 'done');
}
