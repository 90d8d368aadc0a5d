// The std::terminate handler of pre's gmsh child process (child.h): gmsh
// throws std::string (and sometimes std::exception) from inside its OpenMP
// regions, where no catch can reach it; this prints the text for the parent
// and ends the child. Only ever installed in the child.
#include "child.h"

#include <cstdio>
#include <exception>
#include <string>
#include <unistd.h>

namespace
{

[[noreturn]] void child_terminate()
{
    std::string what = "an exception of unknown type";
    try {
        std::exception_ptr current = std::current_exception();
        if (current)
            std::rethrow_exception(current);
        what = "std::terminate without an exception";
    } catch (const std::string &text) {
        what = text;
    } catch (const std::exception &error) {
        what = error.what();
    } catch (const char *text) {
        what = text;
    } catch (...) {
    }
    std::fprintf(stderr, "Exception : %s\n", what.c_str());
    std::fflush(stderr);
    _exit(PRE_CHILD_TERMINATED);
}

} // namespace

extern "C" void pre_child_terminate_install(void)
{
    std::set_terminate(child_terminate);
}
