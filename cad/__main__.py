from cad.cli.app import main

main()
