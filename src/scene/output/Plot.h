#pragma once
/// PNG plots drawn by gnuplot (Debian's gnuplot-nox), written atomically.

#include <string>

namespace masse::scene
{
/// Runs a gnuplot script whose output terminal is set by this function (pngcairo, width x height); the script
/// refers to its output as nothing: plot commands only. Throws std::runtime_error if gnuplot fails or is missing.
void plotPng(const std::string& script, const std::string& pngPath, int width = 1000, int height = 700);
} // namespace masse::scene
