"""The hobbyist's layer beyond the article (screens/97-hobbyist.fs): metric
units, fault injection from the prompt, HOME-POSE and .POSE-METRIC.

Metric units are exact in RCL's own units: with 1 in = 2.54 cm and 625/22
counts an inch (docs/guide.md section 13), a distance of V4
ten-thousandths of a unit is round(V4 x n / 44704) counts, n = 5 MM, 50 CM,
5000 METERS, and a speed of V4 ten-thousandths of a cm/s is
round(V4 x 75 / 5588) crpm (the guide's section 11), round half away from
zero as everywhere in RCL.
"""
from fractions import Fraction

import pytest

import rcl
from rcl.board import NoFaults

MILLI_PER_UNIT = {"MM": 5, "CM": 50, "METERS": 5000}


def rounded(q):
    """Round half away from zero, RCL's rounding."""
    whole = int(abs(q) + Fraction(1, 2))
    return whole if q >= 0 else -whole


def counts(v4, unit):
    return rounded(Fraction(v4 * MILLI_PER_UNIT[unit], 44704))


def typed(v4):
    """V4 as a user types it, with its four decimals: 12345 -> '1.2345'."""
    sign = "-" if v4 < 0 else ""
    return "%s%d.%04d" % (sign, abs(v4) // 10000, abs(v4) % 10000)


def hobbyist(m):
    """m with the layer loaded, as INCLUDE 97-hobbyist.fs loads it."""
    m.evaluate("INCLUDE 97-hobbyist.fs")
    return m


@pytest.fixture(scope="module")
def machine():
    return hobbyist(rcl.open())


def expected(m, text):
    """The counts the next command would move, after `text` gave a distance."""
    m.evaluate(text + " EXPECTED")
    return m.evaluate("D.").strip()


def test_100_cm_is_1118_counts_as_39_3701_inches_and_as_1_meters_and_1000_mm(machine):
    assert expected(machine, "100 CM") == "1118"           # 1,000,000 x 50 / 44704 = 1118.47
    assert expected(machine, "39.3701 INCHES") == "1118"
    assert expected(machine, "1 METERS") == "1118"
    assert expected(machine, "1000 MM") == "1118"


def test_a_metric_distance_is_kept_as_the_articles_inches(machine):
    machine.evaluate("100 CM")                              # 39.37007874 in
    assert machine.evaluate("PENDING 2@ D. PENDING-UNIT ?") == "393701 1 "
    machine.evaluate("PENDING-UNIT OFF")


# Values where rounding to inches first and then to counts would end one
# count off (the first three of each unit from V4 0 up), and plain ones.
TWICE_ROUNDED = {"MM": [4458, 4459, 4460], "CM": [446, 447, 1340],
                 "METERS": [1131, 1283, 2642]}


@pytest.mark.parametrize("unit", sorted(MILLI_PER_UNIT))
def test_metric_counts_are_exact_where_rounding_twice_would_miss(machine, unit):
    values = TWICE_ROUNDED[unit] + [1, 9999, 10000, 123456, 2999999]
    for v4 in values + [-v for v in values]:
        assert expected(machine, "%s %s" % (typed(v4), unit)) == str(counts(v4, unit)), v4


def test_the_twice_rounded_values_really_are_the_hard_ones():
    for unit, values in TWICE_ROUNDED.items():
        for v4 in values:
            inches = rounded(Fraction(v4 * MILLI_PER_UNIT[unit], 127))
            assert rounded(Fraction(inches, 352)) != counts(v4, unit), (unit, v4)


@pytest.mark.parametrize("text, crpm", [("10 CM/S", 1342),     # 100000 x 75 / 5588 = 1342.16
                                        ("25.4 CM/S", 3409),   # = 10 IPS (7.3's table)
                                        ("89.408 CM/S", 12000),  # = 2 MPH, count 125
                                        ("0.0001 CM/S", 1)])
def test_cm_per_second_gives_the_exact_crpm(machine, text, crpm):
    assert machine.evaluate(text + " SPEED .") == "%d " % crpm


def test_cm_per_second_exact_over_a_range_of_speeds(machine):
    for v4 in list(range(1, 400000, 7919)) + [123, 4567, 89012]:
        want = max(1, min(30000, rounded(Fraction(v4 * 75, 5588))))
        assert machine.evaluate("%s CM/S SPEED ." % typed(v4)) == "%d " % want, v4


def test_a_non_positive_speed_is_refused_as_the_articles_are(machine):
    with pytest.raises(rcl.ForthError, match="Bad speed"):
        machine.evaluate("0 CM/S")
    machine.evaluate("1 MPH")


def test_100_cm_forward_drives_the_robot_1118_counts_and_reports_it_in_cm():
    m = hobbyist(rcl.open())
    m.evaluate("RERB 100 CM FORWARD")
    left, right = m.sim.wheel_counts
    assert abs(left - 1118) <= 2 and abs(right - 1118) <= 2   # RUN-ON: 2 counts
    out = m.evaluate(".POSE-METRIC")
    mils = int(m.evaluate("POSE-X 2@ D."))                      # as .POSE-METRIC left it
    hundredths_cm = rounded(Fraction(mils * 127, 500))
    assert out == "x %d.%02d cm  y 0.00 cm  heading 0.0 deg " % (
        hundredths_cm // 100, hundredths_cm % 100)
    assert abs(hundredths_cm - 10000) <= 25                    # 100 cm within a count (0.09 cm)


def test_negative_centimetres_go_the_other_way(machine):
    assert expected(machine, "-50 CM") == "-559"              # -500000 x 50 / 44704 = -559.2


def test_the_arm_takes_centimetres_as_inches():
    m = hobbyist(rcl.open())
    m.evaluate("ARM 5 CM DOWN")                               # 1.9685 in: 197 ticks of 0.01 in
    assert m.sim.arm == pytest.approx(8.0 - 1.97, abs=0.02)


def test_home_pose_zeroes_rcls_pose_without_moving():
    m = hobbyist(rcl.open())
    m.evaluate("RERB 1 FEET FORWARD 90 DEGREES LEFT 200 MS")   # the run-on at rest too
    before = m.sim.wheel_counts
    assert m.evaluate("HOME-POSE .POSE") == "x 0.00 in  y 0.00 in  heading 0.0 deg "
    assert m.sim.wheel_counts == before
    out = m.evaluate("RERB 1 FEET FORWARD .POSE")            # from the new origin, not 24 in
    assert out.startswith("x 12.") or out.startswith("x 11.9"), out


def test_stall_left_stops_the_left_wheel_and_the_move_ends_in_a_following_error():
    m = hobbyist(rcl.open())
    m.evaluate("STALL-LEFT")
    with pytest.raises(rcl.ForthError, match="Following error"):
        m.evaluate("RERB 1 FEET FORWARD")
    left, right = m.sim.wheel_counts
    assert left == 0 and right > 50
    m.evaluate("UNSTALL RERB 1 FEET FORWARD")                  # moves again, no error
    assert m.sim.wheel_counts[0] >= 339


def test_stall_right_and_a_full_load_hold_their_wheel():
    m = hobbyist(rcl.open())
    m.evaluate("STALL-RIGHT")
    with pytest.raises(rcl.ForthError, match="Following error"):
        m.evaluate("RERB 1 FEET FORWARD")
    assert m.sim.wheel_counts[1] == 0
    m.evaluate("NO-FAULTS 100 LOAD-LEFT 200 MS")             # a load of 1: cannot start
    left = m.sim.wheel_counts[0]
    with pytest.raises(rcl.ForthError, match="Following error"):
        m.evaluate("RERB 1 FEET FORWARD")
    assert m.sim.wheel_counts[0] == left
    assert m.sim.drive.left.load == 1.0


def test_a_half_load_slows_the_wheel_but_the_move_completes():
    m = hobbyist(rcl.open())
    m.evaluate("50 LOAD-RIGHT RERB 1 FEET FORWARD")
    assert m.sim.drive.right.load == 0.5
    assert all(abs(c - 341) <= 3 for c in m.sim.wheel_counts)


def test_an_encoder_that_stops_counting_leaves_its_counter_behind_the_wheel():
    m = hobbyist(rcl.open())
    m.evaluate("ENCODER-LEFT-OFF")
    with pytest.raises(rcl.ForthError, match="Following error"):
        m.evaluate("RERB 1 FEET FORWARD")
    assert m.sim.wheel_counts[0] > 50                          # the wheel turned ...
    assert m.evaluate("?CNT1 D. ?CNT2 D.").split()[0] == "0"   # ... its counter saw nothing
    m.evaluate("NO-FAULTS RERB 1 FEET FORWARD")
    assert int(m.evaluate("?CNT1 D.")) >= 339                  # counting again


def test_a_load_out_of_0_to_100_percent_is_refused(machine):
    with pytest.raises(rcl.ForthError, match="Load is 0 to 100 percent"):
        machine.evaluate("101 LOAD-LEFT")
    with pytest.raises(rcl.ForthError, match="Load is 0 to 100 percent"):
        machine.evaluate("-1 LOAD-RIGHT")


@pytest.mark.parametrize("word", ["STALL-LEFT", "STALL-RIGHT", "UNSTALL", "10 LOAD-LEFT",
                                  "10 LOAD-RIGHT", "ENCODER-LEFT-OFF", "ENCODER-RIGHT-OFF",
                                  "NO-FAULTS"])
def test_every_fault_word_is_refused_with_a_clear_message_on_a_board_on_a_link(link, word):
    with pytest.raises(rcl.ForthError, match="Faults are injected on the simulated board only"):
        link.evaluate(word)


@pytest.fixture(scope="module")
def link():
    m = hobbyist(rcl.open(port="rclsim://"))
    yield m
    m.board.close()


def test_the_board_interface_refuses_faults_unless_a_board_has_them():
    from rcl.board import NullBoard
    with pytest.raises(NoFaults):
        NullBoard().inject_fault("stall", "left", 1)


def test_the_layer_is_not_loaded_with_rcl_so_the_articles_runs_stay_as_they_were():
    m = rcl.open()
    assert m.dictionary.find("CM") is None and m.dictionary.find("HOME-POSE") is None
    hobbyist(m)
    assert m.dictionary.find("CM") is not None


def test_the_layer_says_it_is_not_the_articles():
    with open(rcl.SCREENS + "/97-hobbyist.fs") as f:
        first = f.readline()
    assert "not the article's" in first
