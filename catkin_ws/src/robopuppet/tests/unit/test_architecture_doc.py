"""docs/architecture.md's table of nodes and topics against interface.py: every topic name the
table gives is one the nodes share from the interface table, and every topic of interface.py
appears in the table. Every path the
document names exists."""
import pathlib
import re

import pytest

from robopuppet import interface

ROOT = pathlib.Path(__file__).resolve().parents[5]
DOC = ROOT / 'docs' / 'architecture.md'
PACKAGE = ROOT / 'catkin_ws' / 'src' / 'robopuppet'
# Names built by interface.py's functions, as the table writes them.
SIM_NS = interface.sim_ns('R').replace('_R', '_X') + '/'
PREFIXES = (interface.limb_topic('<side>', ''), interface.baxter_gripper_topic('<side>', ''),
            interface.camera_topic('<name>', ''), SIM_NS)
RELATIVE = {interface.JOINT_STATES, interface.USER_BUTTON, interface.HEARTBEAT, interface.OPMODE,
            interface.TELEOP_STATE, interface.GET_CONFIG, interface.SET_CONFIG,
            interface.SET_ARM_CONFIG, interface.STORED_SETTINGS, interface.ACTIVE_SETTINGS,
            interface.LINK_PING, interface.LINK_ECHO, interface.LINK_STATE,
            interface.CALIBRATION_TARGET, interface.ASSIST_TARGET, interface.ASSIST_PREDICTION}
ABSOLUTE = {interface.DIAGNOSTICS, interface.REPLAY_STOP, interface.ZONE_MARKERS,
            interface.ZONE_HOLD_MARKERS, interface.ROOM_MARKERS, interface.ROBOT_STATE,
            interface.ROBOT_JOINT_STATES,
            interface.SET_SUPER_ENABLE, interface.SET_SUPER_RESET, interface.SET_SUPER_STOP,
            interface.RECORD_SERVICE, interface.RECORDING_TOPIC, interface.ASSIST_STATE,
            interface.ASSIST_COMMAND, interface.STUDY_STATE, interface.STUDY_START,
            interface.STUDY_QUESTIONNAIRE, interface.STUDY_MARKERS}
SIM = {interface.SIM_HAND, interface.SIM_BUTTON, interface.SIM_GRIPPERS, interface.SIM_CONTROL,
       interface.SIM_HAND_TORQUE, interface.SIM_LINE_NOISE, interface.SIM_DEVICE_CONFIG,
       interface.SIM_DEVICE_OPMODE}
ROS_OWN = {'/tf_static'}   # ROS's, not ours
NAMESPACE = interface.puppet_ns('R').replace('_R', '_X')   # what <ns> stands for
MARKER_SERVER = interface.marker_server('R').replace('_R', '_X')   # a marker device's server
PER_JOINT = re.compile(r'^(joint_J/(angle|voltage|enc_stat|setpoint|<setting>)|gripper_[G3])$')


def table_text():
    text = DOC.read_text()
    start = text.index('## Nodes and topics')
    return text[start:text.index('\n## ', start + 1)]


def table_names():
    """Return every `/...` or `<ns>/...` name in the table's cells (each cell's first word)."""
    return sorted({name for name in re.findall(r'`([^`\s]+)`', table_text())
                   if name.startswith(('/', '<ns>/'))})


@pytest.mark.parametrize('name', table_names())
def test_each_topic_of_the_table_is_the_interface_tables(name):
    if name.startswith('<ns>/'):
        rest = name[len('<ns>/'):]
        assert rest in RELATIVE or PER_JOINT.match(rest) or rest == '...', name
        return
    prefix = next((p for p in PREFIXES if name.startswith(p)), None)
    if prefix == SIM_NS:
        assert name[len(prefix):] in SIM, name
    elif prefix is None:
        assert name in ABSOLUTE | ROS_OWN | {NAMESPACE, MARKER_SERVER, MARKER_SERVER + '/feedback'
                                              }, name


def test_each_topic_of_the_interface_table_is_in_the_document():
    text = table_text()
    for name in sorted(RELATIVE):
        assert '<ns>/' + name in text, name
    for name in sorted(ABSOLUTE):
        assert '`%s`' % name in text, name
    for name in sorted(SIM):
        assert name in text, name


def test_every_path_the_document_names_exists():
    text = DOC.read_text()
    for path in re.findall(r'`((?:src/robopuppet/|tests/|benchmarks/)[^`*<\s]+)`', text):
        assert (PACKAGE / path).exists() or (PACKAGE / 'src' / 'robopuppet' / path).exists(), path
    for module in re.findall(r'`((?:arm|config|protocol|world|episodes|baxter_sim)/[a-z_]+\.py)`',
                             text):
        assert (PACKAGE / 'src' / 'robopuppet' / module).exists(), module


OUTSIDE = re.compile(r"\b[Ii]ssues? \d+|\bDESIGN(\.md| section)|\bseed's|\b[Ss]eed Table")
TEXT_SUFFIXES = {'.py', '.md', '.launch', '.test', '.sh', '.yaml', '.ini', '.txt', '.xml', '.msg',
                 '.srv', '.urdf', '.rviz', '.nft', ''}
SKIPPED = {'.git', 'build', 'devel', '__pycache__', '.pytest_cache'}


def test_the_repository_cites_nothing_outside_itself():
    # The project's issues and its design page live outside the repository: a reader has only
    # the repository, so docs/architecture.md and the other docs carry what they said.
    found = []
    for path in sorted(ROOT.rglob('*')):
        if SKIPPED & set(path.relative_to(ROOT).parts) or not path.is_file():
            continue
        if path.suffix not in TEXT_SUFFIXES or path.stat().st_size > 2_000_000:
            continue
        try:
            lines = path.read_text().splitlines()
        except UnicodeDecodeError:
            continue
        found += ['%s:%d: %s' % (path.relative_to(ROOT), n, line.strip())
                  for n, line in enumerate(lines, 1) if OUTSIDE.search(line)]
    assert found == []


def readme_layout():
    text = (ROOT / 'README.md').read_text()
    start = text.index('## Layout')
    end = text.find('\n## ', start + 1)
    return text[start:end if end > 0 else None]


def test_the_readme_layout_names_every_folder_and_shared_module():
    layout = readme_layout()
    library = PACKAGE / 'src' / 'robopuppet'
    names = [p.name + '/' for p in library.iterdir() if p.is_dir() and p.name != '__pycache__']
    names += [p.name for p in library.glob('*.py') if p.name != '__init__.py']
    missing = [name for name in sorted(names) if not re.search(r'\b' + re.escape(name), layout)]
    assert missing == []


def test_the_readme_names_every_benchmark():
    text = (ROOT / 'README.md').read_text()
    scripts = [p.name for p in (PACKAGE / 'benchmarks').glob('bench_*.py')
               if "__name__ == '__main__'" in p.read_text()]
    assert scripts and [name for name in sorted(scripts) if '`%s`' % name not in text] == []
