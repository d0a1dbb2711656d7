"""pendulab series --order N [--kind nu|a0|a1|b1|b2...] [--json|--latex|--python]"""


def add_parser(sub):
    p = sub.add_parser(
        "series", help="perturbation series of Mathieu's equation (000 sec. 3) and a_m(q), b_m(q)",
        description="Exact series of theta'' + (theta0 + 2 theta1 cos 2tau) theta = 0 (000 eq. 7). "
                    "Kind 'nu' (default): theta0 = nu^2 + sum alpha_n theta1^n and the coefficients "
                    "c_n, s_n of cos/sin((nu + 2k) tau) (000 eqs. 20-22).  Kinds 'a0', 'a1', 'b1', "
                    "'b2', ...: the characteristic values a_m(q), b_m(q) as power series in q "
                    "(DLMF 28.6, q = -theta1) with their radius of convergence.")
    from pendulab.limits import argument, describe
    argument(p, "--order", "series.order", required=True,
             help=f"highest power of theta1 (or of q for the integer kinds), "
                  f"{describe('series.order')} (order 40 takes about 2 s; the Python API, "
                  "pendulab.analyses.series, goes to 400)")
    p.add_argument("--kind", default="nu", help="nu, or a<m> / b<m> such as a0, b1")
    fmt = p.add_mutually_exclusive_group()
    fmt.add_argument("--json", action="store_true", help="print JSON (sympy-parsable strings)")
    fmt.add_argument("--latex", action="store_true", help="print LaTeX (amsmath align*)")
    fmt.add_argument("--python", action="store_true", help="print the generated Python module")
    p.set_defaults(func=run)
    return p


def run(args):
    from pendulab import limits
    # the order first, without importing SymPy (a usage error answers at once)
    args.order = limits.parse("series.order", args.order, "--order")

    from pendulab.io import canonical_json
    from pendulab.products import series as product
    product.check_request(args.order, [args.kind], where="series")
    if args.json:
        print(canonical_json(product.record(args.kind, args.order)), end="")
        return 0
    if args.latex:
        print(product.latex_text([args.kind], args.order), end="")
        return 0
    if args.python:
        print(product.python_module_text([args.kind], args.order, "the command line"), end="")
        return 0
    rec = product.record(args.kind, args.order)
    if args.kind == "nu":
        print(f"theta0 = nu**2 + sum alpha_n theta1**n, order {args.order} (000 eq. 20)")
        for n, a in sorted(rec["alpha"].items(), key=lambda kv: int(kv[0])):
            print(f"alpha_{n} = {a}")
        print("c_n = sum_k C[n][k] cos((nu + 2k) tau); s_n the same with sin (000 eqs. 21-22)")
        for n, row in sorted(rec["c"].items(), key=lambda kv: int(kv[0])):
            for k, v in row:
                print(f"C[{n}][{k}] = {v}")
        return 0
    print(f"{args.kind}(q) to q**{args.order} (DLMF 28.6); radius of convergence "
          f"{rec['radius']} ({rec['radius_source']})")
    for p, c in sorted(rec["coefficients"].items(), key=lambda kv: int(kv[0])):
        print(f"q**{p}: {c}")
    return 0
