# SPDX-License-Identifier: GPL-3.0-or-later
# Prints $ENV{CAGEKIT_SKIP_MESSAGE} ("SKIP: why"); the test's SKIP_REGULAR_EXPRESSION marks it skipped
# (bindings/CMakeLists.txt, cagekit_skipped_test).
message("$ENV{CAGEKIT_SKIP_MESSAGE}")
