"""``python -m stickslip ARGS...``: the ``stickslip`` command (``stickslip._cli``)."""

from ._cli import main

if __name__ == "__main__":
    main()
