"""Tests of robopuppet.episodes.lerobot_options: each format's options refused with the other."""
import pytest

from robopuppet.episodes import export_cli


@pytest.mark.parametrize('argv, named', [
    (['--fps', '10'], '--fps'),
    (['--puppet'], '--puppet'),
    (['--video-codec', 'av1', '--format', 'csv'], '--video-codec'),
    (['--format', 'lerobot', '--out', 'd', '--rate', '20'], '--rate'),
    (['--format', 'lerobot', '--out', 'd', '--compression', 'gzip'], '--compression'),
    (['--format', 'lerobot', '--out', 'd', '--yes'], '--yes'),
    (['--format', 'lerobot', '--format', 'all', '--out', 'd'], 'goes alone'),
])
def test_an_option_of_the_other_format_is_refused_by_name(capsys, argv, named):
    with pytest.raises(SystemExit):
        export_cli.parse_args(['e'] + argv)
    assert named in capsys.readouterr().err


def test_the_lerobot_defaults_and_the_hdf5_ones_stay_apart():
    args = export_cli.parse_args(['e', '--format', 'lerobot', '--out', 'd'])
    assert (args.fps, args.puppet, args.video_codec, args.image_size) == (30, False, 'h264', None)
    args = export_cli.parse_args(['e', '--format', 'lerobot', '--out', 'd', '--fps', '15',
                                  '--puppet', '--video-codec', 'av1', '--image-size', '320x240'])
    assert (args.fps, args.puppet, args.video_codec, args.image_size) == (15, True, 'av1',
                                                                           (320, 240))
    args = export_cli.parse_args(['e'])
    assert args.formats == {'aloha-hdf5'} and args.fps is None and args.image_size == (320, 240)
