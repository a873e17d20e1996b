"""study: the user-study runner (study_run decides; this adapter starts, records and writes)."""
import os
import sys
import threading

import rospy

from robopuppet import baxter_description, interface as ifc
from robopuppet.periodic import Guard, Loop
from robopuppet.study import input_launch, results, study_cli, study_run, study_topics, summary
from robopuppet_msgs.msg import Questionnaire
from robopuppet_msgs.srv import StudyStart, StudyStartResponse

STEP_S = 0.05          # the runner's step: StudyState at 20 Hz in a trial
COLUMNS = {results.TRIALS_CSV: results.TRIAL_COLUMNS,
           results.QUESTIONNAIRE_CSV: results.QUESTIONNAIRE_COLUMNS}


class StudyNode:
    """Run studies: the GUI's Start (or the command's --participant), each trial's inputs
    (roslaunch robopuppet input.launch per side), the arms to their start before it (rosrun
    robopuppet move_arms), the episode, the judge, the CSV rows.

    ROS API: serves /puppet/study/start (StudyStart); publishes /puppet/study/state (StudyState,
    latched, on change and every 0.5 s, 20 Hz in a trial), /robopuppet/study_task (MarkerArray,
    latched); subscribes /puppet/study/questionnaire, study_topics.StudyWatch's topics; calls
    /puppet/record. Parameters (study_cli.DEFAULTS): ~events ({device: path}), ~results_dir,
    ~study, ~devices, ~tasks, ~practice (1), ~trials (1), ~seed (0), ~trial_timeout (s, 0: the
    task's), ~ready_timeout (s, 60), ~sim_puppet (false), ~input_args (more input.launch args)."""

    def __init__(self, config):
        self._name, self._config, self._lock = rospy.get_name(), config, threading.Lock()
        api, markers, tips_of = study_topics.task_api()
        description = baxter_description.load()
        self._core = study_run.StudyRun(
            api, config['events'], config['study'], config, config['trial_timeout'] or None,
            config['ready_timeout'])
        extra = ['sim_puppet:=%s' % str(config['sim_puppet']).lower()] + config['input_args']
        self._inputs = input_launch.InputProcesses(extra)
        self._move = input_launch.ArmsMove()
        self._watch = study_topics.StudyWatch(lambda n, p: tips_of(description, n, p))
        self._record, self._recording = study_topics.RecordClient(self._name), False
        self._pubs = study_topics.StudyPublishers(markers, os.path.join(
            config['results_dir'], results.TRIALS_CSV))
        rospy.Subscriber(ifc.STUDY_QUESTIONNAIRE, Questionnaire, self._on_answers, queue_size=4)
        rospy.Service(ifc.STUDY_START, StudyStart, self._on_start)
        self._loop = Loop(Guard(self._name, rospy.logerr), 'loop', STEP_S, self._step).start()
        rospy.on_shutdown(self._shutdown)

    def start(self, participant, devices=(), tasks=()):
        """Start a study; return '' or why not (the service's and the command's way in)."""
        with self._lock:
            index = results.participant_index(self._config['results_dir'], participant)
            error, actions = self._core.start(rospy.get_time(), participant, index,
                                              list(devices), list(tasks))
            self._act(actions)
        if not error:
            rospy.loginfo('%s: participant %s started', self._name, participant)
        return error

    def phase(self):
        """Return the study's phase and detail now."""
        with self._lock:
            return self._core.state(rospy.get_time())[::10]

    def _on_start(self, request):
        if request.start:
            error = self.start(request.participant, request.devices, request.tasks)
        else:
            with self._lock:
                error = '' if self._core.phase in study_run.RUNNING else 'no study runs'
                self._act(self._core.stop(rospy.get_time()))
        return StudyStartResponse(not error, error, os.path.join(
            self._config['results_dir'], results.TRIALS_CSV))

    def _on_answers(self, msg):
        with self._lock:
            error, actions = self._core.questionnaire(
                rospy.get_time(), msg.participant, msg.device, list(msg.tlx), list(msg.sus))
            self._act(actions)
        if error:
            rospy.logwarn('%s: questionnaire ignored: %s', self._name, error)

    def _act(self, actions):
        """Carry out the core's actions in order (under the lock)."""
        folder = self._config['results_dir']
        for action in actions:
            if isinstance(action, study_run.StartInputs):
                for command in self._inputs.start(action.device, action.events):
                    rospy.loginfo('%s: %s', self._name, ' '.join(command))
            elif isinstance(action, study_run.StopInputs):
                self._inputs.stop()
                self._move.stop()
            elif isinstance(action, study_run.MoveArms):
                rospy.loginfo('%s: %s', self._name, ' '.join(self._move.start()))
            elif isinstance(action, study_run.Record) and (action.start or self._recording):
                episode = self._record.call(action.start, action.task)
                self._recording = action.start and bool(episode)
                if action.start:
                    self._core.on_episode(rospy.get_time(), episode)
            elif isinstance(action, study_run.WriteRow):
                results.append_row(os.path.join(folder, action.name), COLUMNS[action.name],
                                   action.row)
            elif isinstance(action, study_run.Summarize):
                _, written = summary.write_summary(folder)
                rospy.loginfo('%s: study done: %s', self._name, ', '.join(written))

    def _step(self):
        now = rospy.get_time()
        with self._lock:
            ended = self._inputs.exited()
            if ended and self._core.phase in study_run.RUNNING:
                self._act(self._core.stop(now, 'the input of arm_%s ended (exit %s)' % next(
                    iter(ended.items()))))
            moved = self._move.ended()   # (a failure shows in the state's detail, logged)
            if moved is not None:
                self._act(self._core.on_moved(now, *moved))
            self._act(self._core.step(now, self._watch.seen()))
            state, judge = self._core.state(now), self._core.trial_judge
        if self._pubs.publish(now, state, judge):
            rospy.loginfo('%s: %s: %s', self._name, state.phase, state.detail)

    def _shutdown(self):
        self._loop.stop()
        with self._lock:
            self._act(self._core.stop(rospy.get_time(), 'the study node shut down'))
            self._inputs.stop()


def main():
    """Run the study node; with --participant, one study, exiting with study_cli's codes."""
    args = study_cli.parser().parse_args(rospy.myargv(sys.argv)[1:])
    rospy.init_node('study')
    try:
        rospy.wait_for_service(ifc.STUDY_START, 0.2)
        study_cli.leave(study_cli.EXIT_BUSY, 'another study runner serves ' + ifc.STUDY_START)
    except rospy.ROSException:
        pass
    try:
        node = StudyNode(study_cli.settings(rospy.get_param('~', {}), args))
    except ValueError as error:
        study_cli.leave(study_cli.EXIT_USAGE, error)
    if args.participant is None:
        return rospy.spin()
    error = node.start(args.participant)
    while not error and not rospy.is_shutdown() and node.phase()[0] in study_run.RUNNING:
        rospy.sleep(0.2)
    phase, detail = node.phase()
    rospy.signal_shutdown(error or 'study %s' % phase)
    return study_cli.leave(study_cli.exit_code(error, phase), error or detail)
