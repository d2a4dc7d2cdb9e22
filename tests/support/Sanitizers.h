#pragma once

// Which sanitizer the test binary is built with. GCC defines __SANITIZE_ADDRESS__ and __SANITIZE_THREAD__; clang 14
// (Debian 12's, the one the asan stage builds with) defines neither and answers __has_feature instead, so a test that
// only asks GCC's macro runs unsanitized settings under clang's sanitizers.

namespace masse::test
{
#if defined(__SANITIZE_ADDRESS__)
constexpr bool underAddressSanitizer = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool underAddressSanitizer = true;
#else
constexpr bool underAddressSanitizer = false;
#endif
#else
constexpr bool underAddressSanitizer = false;
#endif

#if defined(__SANITIZE_THREAD__)
constexpr bool underThreadSanitizer = true;
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
constexpr bool underThreadSanitizer = true;
#else
constexpr bool underThreadSanitizer = false;
#endif
#else
constexpr bool underThreadSanitizer = false;
#endif
} // namespace masse::test
