"""The export command's options of --format lerobot, and the checks that keep the formats' options
apart (export_cli parses them; lerobot_export reads them)."""
from robopuppet.episodes import export, lerobot_video

DEFAULT_FPS = 30


def add_arguments(parser):
    """Add the LeRobot options to export's parser (defaults None: given or not is seen)."""
    group = parser.add_argument_group('--format lerobot (one dataset in --out DIR)')
    group.add_argument('--fps', type=int,
                       help='the dataset\'s frames per second (default %d)' % DEFAULT_FPS)
    group.add_argument('--puppet', action='store_true', default=None,
                       help='add observation.puppet_state: the puppets\' own angles')
    group.add_argument('--video-codec', choices=sorted(lerobot_video.CODECS),
                       help='the cameras\' video codec (default %s)' % lerobot_video.DEFAULT_CODEC)


def check_arguments(parser, args, chosen):
    """Check the options against the formats `chosen` (parser.error when one does not apply).

    Returns:
        True for --format lerobot (args completed with its defaults), else False.
    """
    given = [option for option, value in (('--fps', args.fps is not None),
                                          ('--puppet', args.puppet),
                                          ('--video-codec', args.video_codec)) if value]
    if 'lerobot' not in chosen:
        if given:
            parser.error('%s apply to --format lerobot' % ', '.join(given))
        return False
    if chosen != {'lerobot'} or args.plot or args.act_dir:
        parser.error('--format lerobot goes alone (no other format, --plot or --act-dir)')
    others = [option for option, value in (
        ('--rate (use --fps)', args.rate != export.DEFAULT_RATE_HZ),
        ('--compression', args.compression), ('--yes', args.yes)) if value]
    if others:
        parser.error('%s do not apply to --format lerobot' % ', '.join(others))
    if not args.out:
        parser.error('--format lerobot needs --out DIR, the dataset\'s folder')
    args.fps = DEFAULT_FPS if args.fps is None else args.fps
    if args.fps <= 0:
        parser.error('--fps must be a positive whole number')
    args.puppet = bool(args.puppet)
    args.video_codec = args.video_codec or lerobot_video.DEFAULT_CODEC
    args.image_size = args.image_size or None  # default: as recorded
    return True
