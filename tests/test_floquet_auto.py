"""The floquet product's default method "auto": the API's own choice point by point."""

import pytest

from pendulab import limits
from pendulab.analyses.floquet import SIZE_LIMITS
from pendulab.errors import InputError
from pendulab.products import floquet as product


def _options(points, method="auto", dps=30):
    return {"points": points, "ratios": [], "dps": dps, "method": method}


def test_arb_size_of_the_cost_model_is_the_analysis_limit():
    assert limits.ARB_SIZE == SIZE_LIMITS["arb"]


def test_auto_accepts_a_point_beyond_arb_that_hill_takes():
    big = [["1e5", "0.5"]]                      # |theta0| + 2|theta1| = 1e5 + 1 > 3e4
    product.check_options(_options(big))        # auto: hill there, as the API does
    with pytest.raises(InputError, match="method 'arb'"):
        product.check_options(_options(big, method="arb"))


def test_auto_is_priced_as_the_route_it_takes():
    small, big = [["-0.002", "0.2"]], [["1e5", "0.5"]]
    for pts, route in ((small, "arb"), (big, "hill")):
        assert limits.floquet_seconds(pts, [], 30, "auto") == \
            limits.floquet_seconds(pts, [], 30, route)
    # double precision: hill everywhere
    assert limits.floquet_seconds(small, [], None, "auto") == \
        limits.floquet_seconds(small, [], None, "hill")


def test_unknown_method_is_refused_with_auto_named():
    with pytest.raises(InputError, match="auto or one of"):
        product.check_options(_options([["-0.002", "0.2"]], method="fast"))
