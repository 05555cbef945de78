// SPDX-License-Identifier: MIT
/// @file test_pch.cpp
/// The translation unit that builds the test programs' precompiled header (test_pch.h).
