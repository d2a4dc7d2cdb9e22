// The sanitizer build's own check that it sees what the issue found by hand: a double beyond an unsigned 32-bit
// integer's range cast to one (a pinned mass index of 4294967297 once pinned mass 1). GCC's -fsanitize=undefined does
// not include float-cast-overflow; the build adds it by name (MASSE_SANITIZERS). Run with such a number, this program
// must stop with the sanitizer's message and a non-zero exit; if it prints a number instead, the check is off or
// recoverable and the sanitizer stage would miss the fault class it was asked to catch.

#include <cstdint>
#include <cstdio>
#include <cstdlib>

int main(int argc, char** argv)
{
    if (argc != 2)
    {
        std::fprintf(stderr, "usage: sanitizer_canary NUMBER\n");
        return 2;
    }
    // volatile: the cast must happen at run time, on a value the compiler cannot see.
    volatile double value = std::strtod(argv[1], nullptr);
    const std::uint32_t index = static_cast<std::uint32_t>(value);
    std::printf("%u\n", index);
    return 0;
}
