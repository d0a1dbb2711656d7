from pendulab.cli import console

console()
