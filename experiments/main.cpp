// glintlab command line (being wired up).
int main() { return 0; }
