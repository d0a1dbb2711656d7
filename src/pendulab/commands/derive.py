"""pendulab derive kapitza|variable-length [...] [--json|--latex]"""


def add_parser(sub):
    from pendulab.limits import MAX_HARMONICS
    p = sub.add_parser(
        "derive", help="derive the equations of motion of a system",
        description="Derive the equations of motion from the Lagrangian, linearise them "
                    "and bring them to canonical form (Mathieu/Hill or Bessel).  Expressions "
                    "are read without executing them; their limits are in docs/scenes.md.")
    systems = p.add_subparsers(dest="system", metavar="SYSTEM")
    systems.required = True
    k = systems.add_parser(
        "kapitza", help="rigid body on a vertically driven pivot (000)",
        description="Rigid body on a vertically driven pivot (000_8cba66c4fdf94ac6.txt).")
    k.add_argument("--body", choices=("rod", "point", "explicit"), default="rod",
                   help="rod: I = 4 m l^2/3; point: I = m l^2; explicit: I from --inertia")
    k.add_argument("--inertia", metavar="EXPR", help="moment of inertia I about the pivot, "
                   "I >= m l^2 (with --body explicit; default: the symbol I)")
    k.add_argument("--drive", metavar="EXPR", default="a*cos(omega*t)",
                   help="pivot height y0(t), periodic in t, with amplitude a and frequency "
                        "omega; its fundamental frequency w (omega for a*cos(omega*t), 2*omega "
                        f"for a*cos(omega*t)**2) sets tau = w t/2 (at most {MAX_HARMONICS} "
                        "harmonics)")
    k.add_argument("--angle", choices=("up", "down"), default="up",
                   help="measure theta from the upward (source) or downward vertical")
    _formats(k)
    k.set_defaults(func=run)
    v = systems.add_parser(
        "variable-length", help="point mass on a string of length L(t) (002)",
        description="Point mass on a string of varying length (002_19b336b29bb1f03b.txt).")
    v.add_argument("--length", metavar="EXPR", default="L0 + v0*t",
                   help="string length L(t), positive at t = 0")
    v.add_argument("--mass", metavar="EXPR", default="m", help="the mass")
    _formats(v)
    v.set_defaults(func=run)
    return p


def _formats(p):
    g = p.add_mutually_exclusive_group()
    g.add_argument("--json", action="store_true", help="print the JSON record")
    g.add_argument("--latex", action="store_true", help="print a LaTeX fragment")


def run(args):
    from pendulab.errors import InputError, SceneError
    try:
        return _run(args)
    except SceneError as exc:
        # the scene this command made of its options: its keys named as the options
        raise InputError(_as_options(str(exc))) from None


#: the scene keys of ``pendulab derive`` and the options that give them
_OPTION_OF = {"parameters.drive": "--drive", "parameters.body": "--body",
              "parameters.angle": "--angle", "parameters.inertia": "--inertia",
              "parameters.length": "--length", "parameters.mass": "--mass"}


def _as_options(message):
    """``message`` with "command line: parameters.drive:" written "--drive:" (line by line)."""
    lines = []
    for line in message.splitlines():
        head = "command line: "
        if line.startswith(head):
            line = line[len(head):]
            for key, option in _OPTION_OF.items():
                if line.startswith(key + ":") or line.startswith(key + "."):
                    line = option + line[len(key):]
                    break
        lines.append(line)
    return "\n".join(lines)


def _run(args):
    import sys
    from pendulab.scene import parse_scene
    from pendulab.pipeline import Context
    from pendulab.products import equations as product
    from pendulab.io import canonical_json

    params = {}
    if args.system == "kapitza":
        params = {"body": args.body, "drive": args.drive, "angle": args.angle}
        if args.inertia is not None:
            params["inertia"] = args.inertia
    else:
        params = {"length": args.length, "mass": args.mass}
    scene = parse_scene({"name": args.system, "system": args.system, "parameters": params,
                         "products": {"equations": {}}}, path="command line")
    ctx = Context(scene)
    if args.latex:
        sys.stdout.write(product.latex_fragment(ctx, "command line"))
        return 0
    doc = product.document(ctx)
    if args.json:
        sys.stdout.write(canonical_json(doc))
        return 0
    _print_text(doc)
    return 0


def _print_text(doc, indent=""):
    """``doc`` as indented "key: value" lines; a [cosine, sine] pair of strings as
    "cos: ..., sin: ..." (a Hill drive's Fourier coefficients), never a Python repr."""
    for key, value in doc.items():
        if isinstance(value, dict):
            print(f"{indent}{key}:")
            _print_text(value, indent + "  ")
        elif isinstance(value, (list, tuple)) and len(value) == 2 and key.isdigit():
            print(f"{indent}{key}: cos: {value[0]}, sin: {value[1]}")
        elif isinstance(value, (list, tuple)):
            print(f"{indent}{key}: {', '.join(map(str, value))}")
        elif value == "":  # nothing to say (a Mathieu drive's note)
            continue
        else:
            print(f"{indent}{key}: {value}")
