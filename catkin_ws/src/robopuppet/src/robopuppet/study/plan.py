"""A participant's trial list: device blocks in a balanced Latin square's order, practice first.

Pure. The order of the devices (and of the tasks within a block) is a row of a Williams design:
for n conditions, n rows when n is even, 2n when n is odd (each row and its mirror), so that
over a full set of participants each condition comes first equally often and each condition
follows each other one equally often (first-order carry-over balance). Participant k (0-based,
in the order of first appearance in the study's results) takes row k modulo the row count.
"""
import collections
import hashlib

# One trial of the list. number: 1-based in the study; repeat: 1-based among the trials (or
# practice trials) of this device and task; seed: the trial's targets (tasks.make_trial).
PlannedTrial = collections.namedtuple('PlannedTrial',
                                      'number device task practice repeat seed')


class PlanError(ValueError):
    """A study that cannot be planned (no device, a repeated one, a negative count)."""


def williams_rows(n):
    """Return the rows of a Williams design for n conditions, each a list of 0..n-1.

    Row 0 is 0, 1, n-1, 2, n-2, ...; row i adds i (mod n); for odd n the mirrored rows follow.
    """
    if n < 1:
        raise PlanError('a Latin square needs at least one condition')
    first, low, high = [0], 1, n - 1
    while len(first) < n:
        first.append(low)
        low += 1
        if len(first) < n:
            first.append(high)
            high -= 1
    rows = [[(c + i) % n for c in first] for i in range(n)]
    if n % 2:
        rows += [row[::-1] for row in rows]
    return rows


def balanced_order(items, index):
    """Return items in the order of the Williams row for participant `index` (0-based)."""
    items = list(items)
    rows = williams_rows(len(items))
    return [items[c] for c in rows[index % len(rows)]]


def trial_seed(study_seed, participant, device, task, repeat, practice):
    """Return a trial's seed (0..2**32-1): the same for the same inputs, distinct otherwise."""
    text = '%d|%s|%s|%s|%d|%s' % (study_seed, participant, device, task, repeat,
                                   'practice' if practice else 'trial')
    return int.from_bytes(hashlib.sha256(text.encode('utf-8')).digest()[:4], 'big')


def check_counts(devices, tasks, practice, trials):
    """Raise PlanError when the study's devices, tasks or counts cannot make a trial list."""
    for kind, names in (('device', devices), ('task', tasks)):
        if not names:
            raise PlanError('no %s given' % kind)
        repeated = sorted({n for n in names if list(names).count(n) > 1})
        if repeated:
            raise PlanError('%s given twice: %s' % (kind, ', '.join(repeated)))
    if practice < 0 or trials < 1:
        raise PlanError('practice must be 0 or more and trials 1 or more (got %d and %d)'
                        % (practice, trials))


def make_plan(participant, index, devices, tasks, practice=1, trials=1, seed=0):
    """Return the participant's [PlannedTrial]: per device block (in the balanced order of
    `index`), `practice` practice trials of each task, then `trials` trials of each task, the
    tasks in their own balanced order.

    Raises:
        PlanError: see check_counts.
    """
    check_counts(devices, tasks, practice, trials)
    plan = []
    task_order = balanced_order(tasks, index)
    for device in balanced_order(devices, index):
        for is_practice, count in ((True, practice), (False, trials)):
            for repeat in range(1, count + 1):
                for task in task_order:
                    plan.append(PlannedTrial(
                        len(plan) + 1, device, task, is_practice, repeat,
                        trial_seed(seed, participant, device, task, repeat, is_practice)))
    return plan


def blocks(plan):
    """Return the devices of a plan in the order their blocks come."""
    return list(collections.OrderedDict.fromkeys(t.device for t in plan))
