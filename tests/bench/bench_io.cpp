// SPDX-License-Identifier: GPL-3.0-or-later
// bench_io: being written (see tests/bench/README.md).
int main() { return 0; }
