#pragma once
/// Result files: written to a temporary file beside the target, then renamed, so a crash or
/// Ctrl-C never leaves half a file.
#include <stdexcept>
#include <string>

namespace camplace::core {

/// A result file could not be written: the message names the file and gives the system's
/// reason ("DIR/run-1.json: cannot write: No space left on device").
struct WriteError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// The temporary file of a write: `<path>` + kTempSuffix + the writer's pid.
inline constexpr const char* kTempSuffix = ".camplace-tmp";

/// Writes `text` to `path` atomically (creating missing parent directories): to
/// `<path>.camplace-tmp<pid>`, then renamed. Throws WriteError naming the path and errno's reason
/// when it cannot be written; the temporary file is removed on every failure.
void write_file_atomically(const std::string& path, const std::string& text);

/// Throws InputError naming the command-line `option` when no file can be written into the
/// folder `dir` (read-only, full, not permitted), giving errno's reason: checked before the work,
/// so that its result is not lost at the end. Leaves nothing behind.
void probe_writable(const std::string& dir, const std::string& option);

/// Removes from the folder `dir` (not below it) the temporary files `<name>.camplace-tmp<pid>` of
/// write_file_atomically that a killed process left: those whose process no longer runs on this
/// machine and that were last changed at least a minute ago (a write takes far less, and a
/// process of another machine writing into a shared folder is not mistaken for a dead one
/// mid-write). Returns how many it removed; errors are ignored (the files are only clutter).
int remove_stale_temp_files(const std::string& dir);

/// probe_writable on the output directory `dir`, or, when it does not exist yet, on the nearest
/// folder above it that does (where it would be made): nothing is created, so a command stopped
/// before its work leaves no empty folder.
void probe_output_directory(const std::string& dir, const std::string& option);

/// Creates the output directory `dir` (and its parents) before any work is done and checks
/// that files can be written into it (probe_writable); throws InputError naming the
/// command-line `option` when it cannot. Then removes its stale temporary files
/// (remove_stale_temp_files).
void create_output_directory(const std::string& dir, const std::string& option);

}  // namespace camplace::core
