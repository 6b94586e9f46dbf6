"""``placeclust.runner``'s checks of what a user passes as ``--param NAME=VALUE``."""

import pytest

from placeclust.runner import check_params, literal_params


@pytest.mark.parametrize(("algo", "items", "message"), [
    ("online", ["t_new_cluster=abc"], "online's t_new_cluster must be float, got 'abc'"),
    ("online", ["max_places=many"], "max_places must be int | None"),
    ("examples.tiny_recognizer:HaarPlaces", ["threshold=high"], "threshold must be float"),
    ("online", ["radius=2"], "online has no parameter 'radius'"),
])
def test_a_value_of_the_wrong_type_is_refused_before_anything_runs(algo, items, message):
    with pytest.raises(ValueError, match=message):
        check_params(algo, literal_params(items))


def test_values_of_the_right_type_and_text_where_text_is_wanted_pass():
    check_params("online", literal_params(["t_new_cluster=0.9", "view=sides", "max_places=8"]))
    check_params("online", literal_params(["t_new_cluster=1"]))  # an int where a float is
    check_params("kmeans", ["n_clusters"])  # names alone are still checked by name
