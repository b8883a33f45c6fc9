// Run-time options of the sanitizers, built into the test executables so that
// they hold however the tests are started (ctest, or the executable by hand);
// the ASAN_OPTIONS, UBSAN_OPTIONS and TSAN_OPTIONS variables still override them.
// Every report stops the test with a nonzero exit and a stack.
#define GRIDFREE_SANITIZER_OPTIONS                                                          \
  __attribute__((no_sanitize("address", "undefined", "thread"), used, visibility("default")))

extern "C"
{
  GRIDFREE_SANITIZER_OPTIONS const char* __asan_default_options()
  {
    return "detect_leaks=1:strict_init_order=1:check_initialization_order=1";
  }
  GRIDFREE_SANITIZER_OPTIONS const char* __ubsan_default_options()
  {
    return "print_stacktrace=1:halt_on_error=1";
  }
  GRIDFREE_SANITIZER_OPTIONS const char* __tsan_default_options()
  {
    return "halt_on_error=1:second_deadlock_stack=1";
  }
}
