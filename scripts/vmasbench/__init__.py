"""The parts of scripts/bench, its entry point (options, environment, the order of the sections,
bench.md): running (vmas as a subprocess, its JSON summaries, the checks of its output), inputs
(the paper's table, the generated input files and their seeds), sections (what each section
runs), tables (the Markdown and the targets) and plots (the renders and the scaling plot). They
import vmas_files, from scripts/, which the entry point puts on sys.path."""
