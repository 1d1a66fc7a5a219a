"""Issue 33 item 2: the ``--prices`` CSV goes through the one file guard (cad/io/guard.py) and
every price is bounded; a design's dotted keys cannot nest past the limit. Reproducers of
../shared/cases/reliability3/prices-* (inputs built here), and a seeded fuzz of price files:
whatever the bytes, ``load_prices`` returns a table of finite prices in 0..PRICE_MAX or raises
DesignError, never another exception."""

from __future__ import annotations

import math
import os
import random

import pytest

from cad.errors import DesignError, FileRefused
from cad.export.order import apply_prices, load_prices
from cad.io import guard
from cad.tolerances import NESTING_MAX_DEPTH, PRICE_FIELD_MAX_CHARS, PRICE_MAX, READ_MAX_BYTES


def test_fifo_is_refused_without_blocking(tmp_path):
    f = tmp_path / "fifo.csv"
    os.mkfifo(f)
    with pytest.raises(FileRefused, match=r"--prices: .*fifo.csv is a FIFO"):
        load_prices(f)


def test_link_to_dev_zero_is_refused(tmp_path):
    f = tmp_path / "zero.csv"
    f.symlink_to("/dev/zero")
    with pytest.raises(FileRefused, match=r"character device \(a symbolic link to /dev/zero\)"):
        load_prices(f)


def test_file_over_the_limit_is_refused_before_it_is_read(tmp_path):
    f = tmp_path / "big.csv"
    with open(f, "wb") as fh:  # sparse: one byte over the limit, no disk used
        fh.truncate(READ_MAX_BYTES["prices"] + 1)
    with pytest.raises(FileRefused, match=f"is {READ_MAX_BYTES['prices'] + 1} bytes, over the limit"):
        load_prices(f)


def test_field_over_the_csv_limit_is_one_line(tmp_path):
    f = tmp_path / "p.csv"
    f.write_text("designation,unit_price\n" + "y" * 200_000 + ",1\n")
    with pytest.raises(DesignError, match=r"p.csv row 2: not a valid CSV row"):
        load_prices(f)
    f.write_text("designation,unit_price\n" + "y" * (PRICE_FIELD_MAX_CHARS + 1) + ",1\n")
    with pytest.raises(DesignError, match=f"row 2 column designation: a value of {PRICE_FIELD_MAX_CHARS + 1}"):
        load_prices(f)


@pytest.mark.parametrize("value", ["1e308", "inf", "nan", "-1", "1e9000", str(PRICE_MAX * 1.0001)])
def test_price_out_of_range_is_refused(tmp_path, value):
    f = tmp_path / "p.csv"
    f.write_text(f"designation,unit_price\ncrank,{value}\n")
    with pytest.raises(DesignError, match=r"row 2 column unit_price: value .* must be a price in 0\.\.1e\+09"):
        load_prices(f)


def test_largest_prices_keep_the_total_finite(tmp_path):
    """Two lines at PRICE_MAX, bought 1000 times each: the total is exactly 2e12 (closed form)."""
    f = tmp_path / "p.csv"
    f.write_text(f"designation,unit_price\na,{PRICE_MAX:g}\nb,{PRICE_MAX:g}\n")
    rows = [{"part": p, "designation": p, "quantity": 1000, "made_or_bought": "bought", "group": "g"}
            for p in ("a", "b")]
    s = apply_prices(rows, load_prices(f))
    assert s["total_price"] == 2 * 1000 * PRICE_MAX


def test_report_records_the_file_name_only(tmp_path):
    f = tmp_path / "sub" / "p.csv"
    f.parent.mkdir()
    f.write_text("designation,unit_price\ncrank,35\n")
    assert load_prices(f)["source"] == "p.csv"
    assert load_prices(str(f.resolve()))["source"] == "p.csv"


def test_dotted_keys_cannot_nest_past_the_limit(tmp_path):
    for text in ("x" + ".x" * 5000 + " = 1\n", "[" + ".".join(["x"] * 5000) + "]\n"):
        f = tmp_path / "d.toml"
        f.write_text(f'name = "d"\n{text}')
        with pytest.raises(FileRefused, match=r"nested 500[01] levels deep through dotted keys"):
            guard.load_toml(f, "design", "design")
    f.write_text("x" + ".x" * (NESTING_MAX_DEPTH - 1) + " = 1\n")
    assert guard.value_depth(guard.load_toml(f, "design", "design")) == NESTING_MAX_DEPTH


def test_value_depth_closed_forms():
    assert guard.value_depth(1) == 0
    assert guard.value_depth({"a": 1}) == 1
    assert guard.value_depth({"a": [1, {"b": []}]}) == 4  # dict, list, dict, list


_CELLS = ["crank", "618/8 (8x16x4)", "", " ", "1", "0", "-0", "1e308", "nan", "=1+1", '"q""', "a\nb",
          "\x00", "EUR", "1" * 50, "y" * (PRICE_FIELD_MAX_CHARS + 3), "\u0085", "0x10", "1_000"]


def test_fuzz_price_files_refused_in_one_line_or_read(tmp_path):
    """Seeded: 300 random price files (header variants, cells from hostile and plain values,
    random bytes); each gives finite prices in 0..PRICE_MAX or DesignError."""
    rng = random.Random(33)
    f = tmp_path / "p.csv"
    for _ in range(300):
        cols = rng.sample(["designation", "unit_price", "currency", "source", "x"], rng.randint(1, 5))
        lines = [",".join(cols)] + [",".join(rng.choice(_CELLS) for _ in cols)
                                    for _ in range(rng.randint(0, 6))]
        data = "\n".join(lines).encode("utf-8", "surrogatepass")
        if rng.random() < 0.2:
            data += bytes(rng.randrange(256) for _ in range(rng.randint(1, 40)))
        f.write_bytes(data)
        try:
            table = load_prices(f)
        except DesignError:
            continue
        assert all(math.isfinite(v) and 0 <= v <= PRICE_MAX for v in table["prices"].values())
