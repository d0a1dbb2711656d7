"""pendulab build SCENE [--force] [--out DIR] [--replace]"""

import argparse


def add_parser(sub):
    p = sub.add_parser(
        "build", help="build the products a scene file asks for",
        description="Build the products named in a scene file (or in every *.toml of a "
                    "directory) into OUT/<scene name>/.  Only what the products need is "
                    "computed; scenes whose inputs have not changed are skipped.",
        formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    p.add_argument("scene", help="a scene file (derivations/*.toml) or a directory of them")
    p.add_argument("--force", action="store_true", help="rebuild even when up to date")
    p.add_argument("--out", default="generated", help="output root directory")
    p.add_argument("--replace", action="store_true",
                   help="replace the outputs of a scene of the same name built from another "
                        "scene file (refused without it)")
    p.set_defaults(func=run)
    return p


def run(args):
    from pendulab.build import build, check_out_root
    check_out_root(args.out, "--out")  # before reading or computing anything
    build(args.scene, out_root=args.out, force=args.force, replace=args.replace)
    return 0
