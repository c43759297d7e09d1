// host/cli/commands.h - the sub-commands of `articula`. Each owns its options, prints
// its own --help, and returns the process exit code.
#ifndef ARTICULA_CLI_COMMANDS_H
#define ARTICULA_CLI_COMMANDS_H

namespace articula::cli {

int cmd_info(int argc, char** argv);
int cmd_fk(int argc, char** argv);
int cmd_ik(int argc, char** argv);
int cmd_export_urdf(int argc, char** argv);
int cmd_quantize(int argc, char** argv);
int cmd_predict(int argc, char** argv);
int cmd_run(int argc, char** argv);
int cmd_import_legacy(int argc, char** argv);
int cmd_sim(int argc, char** argv);
int cmd_configure(int argc, char** argv);
int cmd_draw(int argc, char** argv);
int cmd_wiring(int argc, char** argv);
int cmd_mat(int argc, char** argv);

}  // namespace articula::cli

#endif
