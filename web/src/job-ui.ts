// A job's progress in the panel: a progress bar with the stage name, the state in words (the error's
// message and field when it failed) and a Cancel button. Test ids: <prefix>-progress, <prefix>-state,
// <prefix>-cancel.
import { api, ApiError } from './api.ts';
import { collection, events, terminal, type Job } from './events.ts';
import { el } from './dom.ts';

export { el };

/** An error in words: the message, and the field it names. */
export function errorText(e: { message?: string; field?: string } | null | undefined): string {
  if (!e) return 'unknown error';
  const msg = e.message || 'unknown error';
  return e.field ? `${msg} (field: ${e.field})` : msg;
}

export class JobView {
  readonly el: HTMLElement;
  private bar: HTMLProgressElement;
  private label: HTMLElement;
  private state: HTMLElement;
  private cancel: HTMLButtonElement;
  private job: Job | null = null;
  private unwatch: (() => void) | null = null;

  constructor(readonly prefix: string) {
    this.el = el('div', { class: 'plan-job', hidden: '' });
    const row = el('div', { class: 'plan-job-row' });
    this.bar = el('progress', { max: '1', value: '0', 'data-testid': `${prefix}-progress` });
    this.cancel = el('button', { type: 'button', 'data-testid': `${prefix}-cancel`, class: 'plan-small' }, 'Cancel');
    row.append(this.bar, this.cancel);
    this.label = el('div', { class: 'plan-job-stage muted' });
    this.state = el('div', { class: 'plan-job-state', 'data-testid': `${prefix}-state`, role: 'status' });
    this.el.append(row, this.label, this.state);
    this.cancel.addEventListener('click', () => void this.doCancel());
  }

  get busy(): boolean {
    return this.job !== null && !terminal(this.job.state);
  }

  /** Submits a job and follows it; resolves with its final state (null when submitting failed). */
  run(submit: () => Promise<Job>): Promise<Job | null> {
    this.unwatch?.();
    this.el.hidden = false;
    this.show({ state: 'queued', progress: 0, stage: '' } as Job);
    this.state.textContent = 'Submitting…';
    return new Promise((resolve) => {
      submit().then(
        (job) => {
          this.show(job);
          this.unwatch = events.watch(
            job.kind,
            job.id,
            (j) => {
              this.show(j);
              if (terminal(j.state)) resolve(j);
            },
            (e) => {
              this.fail(e);
              resolve(null);
            },
          );
        },
        (e: unknown) => {
          this.fail(e);
          resolve(null);
        },
      );
    });
  }

  private fail(e: unknown): void {
    this.job = null;
    this.cancel.disabled = true;
    this.state.className = 'plan-job-state plan-error';
    this.state.textContent =
      e instanceof ApiError ? `Failed: ${errorText(e)}` : `Failed: ${e instanceof Error ? e.message : String(e)}`;
  }

  private show(job: Job): void {
    this.job = job.id ? job : this.job;
    this.bar.value = job.state === 'done' ? 1 : Math.max(0, Math.min(1, job.progress || 0));
    this.cancel.disabled = terminal(job.state) || job.cancel_requested === true;
    // the stage is what a running job is doing: a finished one has none left
    this.label.textContent = job.stage && !terminal(job.state) ? `stage: ${job.stage}` : '';
    this.state.className = 'plan-job-state';
    this.state.dataset.state = job.state;
    switch (job.state) {
      case 'queued':
        this.state.textContent = 'Queued';
        break;
      case 'running':
        this.state.textContent = `Running — ${Math.round(100 * (job.progress || 0))} %${
          job.cancel_requested ? ' (cancelling…)' : ''
        }`;
        break;
      case 'done':
        this.state.textContent = 'Done';
        break;
      case 'cancelled':
        this.state.textContent = 'Cancelled';
        break;
      case 'failed':
        this.state.className = 'plan-job-state plan-error';
        this.state.textContent = `Failed: ${errorText(job.error)}`;
        break;
    }
  }

  private async doCancel(): Promise<void> {
    if (!this.job || terminal(this.job.state)) return;
    this.cancel.disabled = true;
    try {
      const j = await api.del<Job>(`/${collection(this.job.kind)}/${this.job.id}`);
      this.show(j);
    } catch (e) {
      this.fail(e);
    }
  }
}
