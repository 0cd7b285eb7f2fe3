// The all-modules check configures (does not build) this program: generating its link line
// resolves every MANTA target and its dependencies (tests/install/install_test.sh).
int main() {
    return 0;
}
