"""study_summary: a study's table per device (summary.csv, summary.md) and its plots (PNG).

Pure (files, numpy, matplotlib through png_plot: no display needed). Practice trials are
left out; a device's TLX and SUS are the means over its questionnaires.
"""
import argparse
import os
import sys

import numpy as np

from robopuppet import png_plot
from robopuppet.study import results

SUMMARY_CSV = 'summary.csv'
SUMMARY_MD = 'summary.md'
SUMMARY_COLUMNS = ('device', 'trials', 'success_rate', 'median_completion_s', 'median_path_m',
                   'tlx_mean', 'sus_mean', 'participants')
PLOTS = {'time': 'plot_time.png', 'success': 'plot_success.png', 'tlx': 'plot_tlx.png'}


def _number(text):
    """Return a CSV cell as a float, nan when empty or not a number."""
    try:
        return float(text)
    except (TypeError, ValueError):
        return float('nan')


def _median(values):
    values = [v for v in values if np.isfinite(v)]
    return float(np.median(values)) if values else float('nan')


def _mean(values):
    values = [v for v in values if np.isfinite(v)]
    return float(np.mean(values)) if values else float('nan')


def summarize(trial_rows, questionnaire_rows):
    """Return one dict per device (SUMMARY_COLUMNS), in the order devices first appear.

    completion times count successful trials only (a failed trial has no completion time);
    the median path counts every trial.
    """
    devices = []
    for row in list(trial_rows) + list(questionnaire_rows):
        if row['device'] not in devices:
            devices.append(row['device'])
    table = []
    for device in devices:
        rows = [r for r in trial_rows if r['device'] == device and r['practice'] != 'true']
        answers = [r for r in questionnaire_rows if r['device'] == device]
        success = [r['success'] == 'true' for r in rows]
        table.append({
            'device': device, 'trials': len(rows),
            'success_rate': float(np.mean(success)) if rows else float('nan'),
            'median_completion_s': _median(_number(r['completion_s'])
                                           for r, ok in zip(rows, success) if ok),
            'median_path_m': _median(_number(r['path_m']) for r in rows),
            'tlx_mean': _mean(_number(r['tlx']) for r in answers),
            'sus_mean': _mean(_number(r['sus']) for r in answers),
            'participants': len({r['participant'] for r in rows})})
    return table


def _text(value, digits=2):
    if isinstance(value, float):
        return '-' if not np.isfinite(value) else '%.*f' % (digits, value)
    return str(value)


def markdown(table, title):
    """Return the table as Markdown, a title line first."""
    lines = ['# %s' % title, '',
             '| device | trials | success | median time (s) | median path (m) | TLX | SUS |'
             ' participants |', '|' + '---|' * 8]
    for row in table:
        rate = row['success_rate']
        lines.append('| %s | %d | %s | %s | %s | %s | %s | %d |' % (
            row['device'], row['trials'], '-' if not np.isfinite(rate) else '%.0f %%' % (
                100 * rate), _text(row['median_completion_s'], 1), _text(row['median_path_m']),
            _text(row['tlx_mean'], 1), _text(row['sus_mean'], 1), row['participants']))
    return '\n'.join(lines) + '\n'


def write_plots(results_dir, trial_rows, table):
    """Write the PNG plots: completion time per device (box plot of successful trials), success
    rate and mean TLX (bars). Returns their paths."""
    plt = png_plot.pyplot()
    devices = [row['device'] for row in table]
    times = [[_number(r['completion_s']) for r in trial_rows if r['device'] == d
              and r['practice'] != 'true' and r['success'] == 'true'] for d in devices]
    paths = []
    for key, ylabel in (('time', 'completion time (s)'), ('success', 'success rate (%)'),
                        ('tlx', 'NASA-TLX raw (0..100)')):
        figure, axis = plt.subplots(figsize=(6, 4))
        if key == 'time':
            shown = [t if t else [float('nan')] for t in times]
            axis.boxplot(shown, labels=devices)
        else:
            values = [100 * r['success_rate'] if key == 'success' else r['tlx_mean']
                      for r in table]
            axis.bar(devices, np.nan_to_num(values))
        axis.set_ylabel(ylabel)
        axis.set_title('%s per device' % ylabel.split(' (')[0])
        path = os.path.join(results_dir, PLOTS[key])
        png_plot.write_png(path, figure)
        paths.append(path)
    return paths


def write_summary(results_dir, plots=True):
    """Read a study's CSV files and write summary.csv, summary.md and (plots) the PNG plots.

    Returns:
        (the table, [paths written]).
    Raises:
        FileNotFoundError: the folder has no trials.csv.
    """
    trials_path = os.path.join(results_dir, results.TRIALS_CSV)
    if not os.path.exists(trials_path):
        raise FileNotFoundError('no %s in %s' % (results.TRIALS_CSV, results_dir))
    trial_rows = results.read_rows(trials_path)
    table = summarize(trial_rows, results.read_rows(
        os.path.join(results_dir, results.QUESTIONNAIRE_CSV)))
    csv_path = os.path.join(results_dir, SUMMARY_CSV)
    if os.path.exists(csv_path):
        os.remove(csv_path)
    for row in table:
        results.append_row(csv_path, SUMMARY_COLUMNS, row)
    md_path = os.path.join(results_dir, SUMMARY_MD)
    with open(md_path, 'w', encoding='utf-8') as handle:
        handle.write(markdown(table, 'Study %s' % os.path.basename(
            os.path.normpath(results_dir))))
    written = [csv_path, md_path]
    if plots and table:
        written += write_plots(results_dir, trial_rows, table)
    return table, written


def main(argv=None):
    """study_summary DIR: write the summary of a study's results folder; exit 0, 1 without
    trials.csv, 2 on bad arguments."""
    parser = argparse.ArgumentParser(
        prog='study_summary', description='Summarise a user study: per device the trials, '
        'success rate, median completion time and path, TLX and SUS means (summary.csv, '
        'summary.md) and plots (plot_*.png), written into the study folder.')
    parser.add_argument('results_dir', help='the study folder (holds trials.csv)')
    parser.add_argument('--no-plots', action='store_true', help='write the tables only')
    args = parser.parse_args(argv)
    try:
        _, written = write_summary(args.results_dir, plots=not args.no_plots)
    except (OSError, results.ResultsError) as error:
        print('study_summary: %s' % error, file=sys.stderr)
        return 1
    with open(written[1], encoding='utf-8') as handle:
        print(handle.read(), end='')
    print('written: %s' % ', '.join(written))
    return 0
