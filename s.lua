print(pcall(require("lancer").load_png, "big.png"))
