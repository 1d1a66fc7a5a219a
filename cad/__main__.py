from cad.cli.entry import main

main()
