"""Command line: ``masonrydem --version``."""
import argparse

from . import __version__


def main(argv=None):
    parser = argparse.ArgumentParser(prog="masonrydem", description=__doc__)
    parser.add_argument("--version", action="version", version=f"masonrydem {__version__}")
    parser.parse_args(argv)
    parser.print_help()
    return 0
