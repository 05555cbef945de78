// SPDX-License-Identifier: MIT
/// @file stb_instrumented.cpp
/// stb_image's decoders compiled into the fuzz targets, with coverage and sanitizers, in place of
/// Debian's prebuilt libstb (the definitions here interpose its symbols).
#define STB_IMAGE_IMPLEMENTATION
#include <stb_image.h>
