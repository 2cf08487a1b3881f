"""What a study's analysis needs, in numbers of runs: read by `masonrydem
check` before anything is drawn or run, so this module imports nothing
(the analysis's modules load pandas and scipy.stats)."""
FRACTILE = 0.05          # the characteristic value of EN 1990 and EN 1996: the 5 % fractile
CONFIDENCE = 0.95        # of the fractiles' intervals
MIN_RUNS = 10            # the runs a group's Sobol indices need (sensitivity.py)


def lower_end_runs(p=FRACTILE, confidence=CONFIDENCE):
    """The fewest runs whose order statistics give the p-fractile's
    interval a lower end (fractiles.order_ranks): the smallest n with
    (1 - p)^n <= (1 - confidence) / 2, the probability that no run of n
    falls below the fractile."""
    a, n = (1 - confidence) / 2, 1
    while (1 - p) ** n > a:
        n += 1
    return n
