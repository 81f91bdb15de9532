// Unsaved edits are never dropped without a word (issue 29, defect 3): before the Define tab's document
// is replaced (another mission opened, a new one, an import), the operator is asked in the page; a
// reload or leaving the page is asked by the browser (main.ts, beforeunload).
import type { App } from './state.ts';

/** Resolves true when the document may be replaced: nothing unsaved, or the operator discards it. */
export function confirmDiscard(app: App, what: string): Promise<boolean> {
  const s = app.state;
  if (!s.dirty || !s.mission) return Promise.resolve(true);
  document.querySelector('[data-testid=discard-dialog]')?.remove();
  return new Promise((resolve) => {
    const box = document.createElement('div');
    box.className = 'discard-dialog';
    box.setAttribute('role', 'alertdialog');
    box.setAttribute('aria-modal', 'true');
    box.dataset.testid = 'discard-dialog';
    const name = typeof s.mission?.name === 'string' ? `“${s.mission.name}”` : 'the mission';
    const msg = document.createElement('p');
    msg.textContent = `${s.missionId === null ? `The new mission ${name} is not saved` : `Mission #${s.missionId} ${name} has unsaved changes`}. ${what} anyway and lose them?`;
    const keep = document.createElement('button');
    keep.type = 'button';
    keep.dataset.testid = 'discard-cancel';
    keep.textContent = 'Keep editing';
    const drop = document.createElement('button');
    drop.type = 'button';
    drop.className = 'danger';
    drop.dataset.testid = 'discard-confirm';
    drop.textContent = 'Discard the changes';
    const row = document.createElement('div');
    row.className = 'discard-row';
    row.append(keep, drop);
    box.append(msg, row);
    const done = (ok: boolean) => {
      box.remove();
      document.removeEventListener('keydown', onKey, true);
      if (!ok) app.showTab('define');
      resolve(ok);
    };
    const onKey = (e: KeyboardEvent) => {
      if (e.key === 'Escape') {
        e.stopPropagation();
        done(false);
      }
    };
    keep.addEventListener('click', () => done(false));
    drop.addEventListener('click', () => done(true));
    document.addEventListener('keydown', onKey, true);
    document.body.append(box);
    keep.focus();
  });
}
